// The progress line of a long episode.
#include <gtest/gtest.h>

#include "valerant/explore/progress_line.h"

using namespace valerant;

TEST(ProgressLine, SaysStepCandidateCoverageKeyframesMemoryAndSeconds) {
  StepRecord step;
  step.step = 12;
  step.committed_steps = 9;
  step.candidates.resize(2);
  step.candidates[1].verdict.candidate = "jw";
  step.chosen = 1;
  step.rewind = true;
  step.map_keyframes = 120;
  StepProgress progress;
  progress.observed_percent = 13.44;
  progress.resident_bytes = 812ull * 1024 * 1024 + 1000;  // whole MB, rounded down
  progress.seconds = 4.214;
  progress.total_seconds = 125.26;
  EXPECT_EQ(progressLine(step, progress),
            "step 12 | committed 9 | jw + rewind | observed 13.4 % | keyframes 120 | memory 812 MB | 4.21 s, 125.3 s total");
  step.chosen = -1;
  step.rewind = false;
  progress.observed_percent.reset();  // no ground truth
  progress.as_recorded = true;
  EXPECT_EQ(progressLine(step, progress),
            "step 12 | committed 9 | stall (as recorded) | keyframes 120 | memory 812 MB | 4.21 s, 125.3 s total");
}
