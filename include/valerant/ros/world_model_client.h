#pragma once
// The WorldModel interface over the world_model_server's services and Rollout action,
// so Episode runs unchanged against a world model in another process (or on another
// host). A rollout's frames stream from the server straight to the branch_slam nodes;
// the Rollout handed back here carries the id, the candidate and the frames' ground
// truth without images, which is all the explorer needs.
#include <actionlib/client/simple_action_client.h>
#include <ros/node_handle.h>
#include <valerant/RolloutAction.h>

#include "valerant/ros/service_call.h"
#include "valerant/world/world_model.h"

namespace valerant::bridge {

class WorldModelClient : public WorldModel {
 public:
  // Waits up to `connect_timeout_s` for the server; `rollout_timeout_s` bounds one rollout.
  WorldModelClient(::ros::NodeHandle nh, double connect_timeout_s, double rollout_timeout_s);

  CameraIntrinsics intrinsics() const override { return intrinsics_; }
  Rollout context() const override;
  CheckpointId checkpoint() override;
  void restore(CheckpointId id) override;
  void dropCheckpoint(CheckpointId id) override;
  Rollout rollout(const ActionSequence& actions) override;
  void commit(const Rollout& rollout) override;
  // Back to the spawn: a new episode.
  void reset();

 private:
  ::ros::NodeHandle nh_;
  double rollout_timeout_s_;
  mutable ServiceLink checkpoint_, restore_, drop_, commit_, reset_, get_rollout_;
  actionlib::SimpleActionClient<valerant::RolloutAction> rollout_;
  CameraIntrinsics intrinsics_;
  CheckpointId current_ = 0;  // checkpoint the committed state stands at (0: none)
};

}  // namespace valerant::bridge
