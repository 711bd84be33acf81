#pragma once
// Action selection, paper eq. 2:
//   m* = argmax_{m admissible} lambda_cov C_m + lambda_prog P_m  [+ goal_weight G_m + opening_weight O_m]
// (the bracketed whole-level terms are [ours], 0 by the paper: docs/whole_level.md).
// A candidate is admissible when neither collision test fired (B = 0), its SLAM did
// not lose track and it does not enter the failed-region memory ([ours]: and a short
// translation is clear to its end, branch_verdict.h; and its reconstructed motion P is
// at most policy.max_progress forward actions: more is a SLAM scale runaway). Ties go to the
// candidate listed first (the paper's order uw, jw, lw, jq, lq), so a run is
// deterministic. No admissible candidate: a stall (returns -1). [ours] With
// policy.no_turn_back, a turn in place that undoes the last committed one (turns_back,
// turn_back.h) is chosen only when no other candidate is admissible.
// [ours] With policy.yielding_objections, when no translation is admissible, a
// translation whose only objections are listed there is admitted (`yielded`).
//
// Baselines (policy.kind) choose among the same admissible candidates:
//   random   - uniformly, from a generator seeded by (seed, step);
//   forward  - uw whenever admissible, else the first admissible rotation, else any;
//   frontier - the largest C_front (closest to the frontier), ties by coverage.
#include <cstdint>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/explore/branch_verdict.h"

namespace valerant {

// A translation nothing objects to was judged: the agent moves on. A yielded one does
// not count: it is the last resort, and a later round may still offer a clear one.
bool movesOn(const std::vector<BranchVerdict>& verdicts);

// Fills score, admissible and reason of every verdict; returns the chosen index or -1.
// `step_seed` only feeds the random baseline.
int selectBranch(std::vector<BranchVerdict>& verdicts, const PolicyConfig& config, uint64_t step_seed = 0);

}  // namespace valerant
