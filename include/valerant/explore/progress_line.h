#pragma once
// The line a long episode prints on stderr after every step, e.g.
//   step 12 | committed 9 | jw + rewind | observed 13.4 % | keyframes 120 | memory 812 MB | 4.21 s, 125.3 s total
// "observed" (the reachable floor the map observes, eval/live_coverage.h) is left out
// where there is no ground truth; a stall shows "stall" for the candidate.
#include <optional>
#include <string>

#include "valerant/explore/episode.h"

namespace valerant {

struct StepProgress {
  std::optional<double> observed_percent;  // none without ground truth
  uint64_t resident_bytes = 0;             // this process's resident memory after the step
  double seconds = 0;                      // the step, its outputs included
  double total_seconds = 0;                // since the episode started
  bool as_recorded = false;                // a resumed run's replayed step
};

std::string progressLine(const StepRecord& step, const StepProgress& progress);

}  // namespace valerant
