#pragma once
// The `bag` world model backend: replays the rollouts a graph
// recorded (record.launch) keyed by (checkpoint id, candidate), so the downstream
// pipeline re-runs bit for bit without the engine. Checkpoint ids are issued exactly as
// the recording world issued them (1, 2, ...), so a replay that makes the same
// decisions asks for exactly the recorded rollouts; one that diverges gets an
// InputError naming the missing (checkpoint, candidate).
#include <map>
#include <memory>
#include <rosbag/bag.h>
#include <rosbag/message_instance.h>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "valerant/world/world_model.h"

namespace valerant::bridge {

class BagWorld : public WorldModel {
 public:
  // `prefix`: the recorded graph's namespace ("/" for the root). Throws InputError naming
  // the bag for an unreadable or corrupt one, one without camera_info or context, and one
  // recorded before the frames were PNG-compressed (an older valerant/Frame format).
  BagWorld(const std::string& path, const std::string& prefix);

  CameraIntrinsics intrinsics() const override { return intrinsics_; }
  Rollout context() const override { return context_; }
  CheckpointId checkpoint() override;
  void restore(CheckpointId id) override;
  void dropCheckpoint(CheckpointId id) override { checkpoints_.erase(id); }
  Rollout rollout(const ActionSequence& actions) override;
  void commit(const Rollout& rollout) override;

 private:
  std::string path_;
  std::unique_ptr<rosbag::Bag> bag_;
  CameraIntrinsics intrinsics_;
  Rollout context_;
  std::map<std::pair<CheckpointId, std::string>, std::vector<rosbag::MessageInstance>> rollouts_;
  std::map<CheckpointId, size_t> checkpoints_;  // id -> frames committed then
  CheckpointId next_checkpoint_ = 1, current_ = 0;
  std::map<RolloutId, size_t> pending_;         // rollout id -> its frame count
  RolloutId next_rollout_ = 1;
  size_t frames_committed_ = 0;
};

}  // namespace valerant::bridge
