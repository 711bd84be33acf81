#pragma once
// The BranchPipeline interface over the node graph: checkpoints, restores, drops and
// commits go to the five branch SLAMs, the floor_estimator and the collision_checker
// (in parallel, all under the world model's checkpoint id); a candidate's evaluation is the BranchResult
// that collision_checker publishes once the candidate's frames have passed
// branch_slam -> floor_estimator -> collision_checker.
#include <condition_variable>
#include <map>
#include <mutex>
#include <ros/node_handle.h>
#include <ros/subscriber.h>
#include <string>
#include <valerant/CandidateResult.h>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/explore/branch_pipeline.h"
#include "valerant/ros/service_call.h"

namespace valerant::bridge {

class RosBranchPipeline : public BranchPipeline {
 public:
  // `connect_timeout_s` bounds the wait for the nodes, `result_timeout_s` one evaluation.
  RosBranchPipeline(::ros::NodeHandle nh, double connect_timeout_s, double result_timeout_s);

  BranchResult start(const Rollout& context) override;
  void checkpoint(CheckpointId id) override;
  void restore(CheckpointId id) override;
  void drop(CheckpointId id) override;
  std::future<BranchResult> evaluate(Rollout rollout, bool rotation_only, std::vector<size_t> keep_after) override;
  void commit(const BranchResult& chosen) override;
  FloorPlane floorAt(const Eigen::Isometry3d& camera_to_map) override;

 private:
  // Calls `leaf` on every branch SLAM, the floor estimator and the collision checker,
  // in parallel.
  template <class Service>
  void callAll(const std::string& leaf, const typename Service::Request& request);
  // A persistent link to each of `names`, all services of type `Service`.
  template <class Service>
  void addLinks(const std::vector<std::string>& names);
  // The floor estimator's, the collision checker's and every branch SLAM's service `leaf`.
  static std::vector<std::string> allNames(const std::string& leaf);
  void onResult(const valerant::CandidateResult::ConstPtr& msg);
  BranchResult waitForResult(Rollout rollout, bool rotation_only);

  ::ros::NodeHandle nh_;
  double result_timeout_s_;
  std::map<std::string, ServiceLink> links_;  // by service name; used by the episode's calls only
  std::vector<::ros::Subscriber> results_;
  std::mutex mutex_;
  std::condition_variable arrived_;
  std::map<RolloutId, valerant::CandidateResult::ConstPtr> received_;
};

}  // namespace valerant::bridge
