#pragma once
// The BranchSelector interface over the policy_arbiter node's select_branch service
// (which runs selectBranch() with the graph's policy config).
#include <ros/node_handle.h>

#include "valerant/explore/branch_selector.h"
#include "valerant/ros/service_call.h"

namespace valerant::bridge {

class ArbiterClient : public BranchSelector {
 public:
  ArbiterClient(::ros::NodeHandle nh, double connect_timeout_s);
  int select(std::vector<BranchVerdict>& verdicts, uint64_t step_seed) override;

 private:
  ServiceLink client_;
};

}  // namespace valerant::bridge
