// Coverage against committed step and wall time, on a hand-made history with a stall and
// a rewind.
#include <gtest/gtest.h>

#include "valerant/common/error.h"
#include "valerant/eval/coverage_curve.h"

using namespace valerant;

namespace {

StepRecord step(bool commits, bool rewind, int committed_after, double seconds) {
  StepRecord s;
  s.chosen = commits ? 0 : -1;
  s.rewind = rewind;
  s.committed_steps = committed_after;
  s.wall_seconds = seconds;
  return s;
}

}  // namespace

TEST(CoverageCurve, KeptStepsWithTheWallSecondsSpentToReachThem) {
  // commit (1), stall (1), commit (2), commit then rewind to 1, commit (2), commit (3).
  const std::vector<StepRecord> history = {step(true, false, 1, 2), step(false, false, 1, 1), step(true, false, 2, 3),
                                           step(true, true, 1, 2),  step(true, false, 2, 1), step(true, false, 3, 2)};
  const CoverageCurve c = coverageByCommittedStep(history, {5, 5, 8, 5, 9, 12});
  EXPECT_EQ(c.committed_step, (std::vector<int>{1, 2, 3}));
  // Step 1 is the first commit (2 s); step 2 the one made again after the rewind
  // (2 + 1 + 3 + 2 + 1 = 9 s); step 3 the last (11 s).
  EXPECT_EQ(c.observed_percent, (std::vector<double>{5, 9, 12}));
  EXPECT_EQ(c.wall_seconds, (std::vector<double>{2, 9, 11}));
}

TEST(CoverageCurve, StepsDroppedByAFinalRewindAreNotInIt) {
  const std::vector<StepRecord> history = {step(true, false, 1, 1), step(true, false, 2, 1), step(true, true, 1, 1)};
  const CoverageCurve c = coverageByCommittedStep(history, {3, 6, 3});
  EXPECT_EQ(c.committed_step, (std::vector<int>{1}));
  EXPECT_EQ(c.wall_seconds, (std::vector<double>{1}));
  EXPECT_TRUE(coverageByCommittedStep({}, {}).committed_step.empty());
  EXPECT_THROW(coverageByCommittedStep(history, {1}), InputError);
  // A map never tied to the world has no per-step figures: 0 % at every kept step.
  EXPECT_EQ(coverageByCommittedStep(history, {}).observed_percent, (std::vector<double>{0}));
}
