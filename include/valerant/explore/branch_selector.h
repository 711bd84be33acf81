#pragma once
// The choice among the judged candidates of one step (paper eq. 2). Episode asks a
// BranchSelector; in this process that is selectBranch() itself, in the ROS graph a
// client of the policy_arbiter node, which runs the same selectBranch().
#include <cstdint>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/explore/branch_verdict.h"
#include "valerant/explore/policy.h"

namespace valerant {

class BranchSelector {
 public:
  virtual ~BranchSelector() = default;
  // Fills score, admissible and reason of every verdict; returns the chosen index or
  // -1 (a stall). `step_seed` only feeds the random baseline.
  virtual int select(std::vector<BranchVerdict>& verdicts, uint64_t step_seed) = 0;
};

class PolicyBranchSelector : public BranchSelector {
 public:
  explicit PolicyBranchSelector(const PolicyConfig& config) : config_(config) {}
  int select(std::vector<BranchVerdict>& verdicts, uint64_t step_seed) override {
    return selectBranch(verdicts, config_, step_seed);
  }

 private:
  PolicyConfig config_;
};

}  // namespace valerant
