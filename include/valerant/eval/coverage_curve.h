#pragma once
// Coverage against committed step and against wall time: for the k-th committed step of
// the kept path (k = 1 .. the episode's committed steps), the reachable floor observed
// and the wall seconds the episode had spent when that step was committed. The k-th
// step is the last commit that brought the count to k (a rewind drops steps; the ones
// made again replace them); the wall seconds count every step before it, rewound and
// stalled ones too: what reaching that coverage cost.
#include <vector>

#include "valerant/explore/episode.h"

namespace valerant {

struct CoverageCurve {
  std::vector<int> committed_step;        // 1, 2, ..., K
  std::vector<double> observed_percent;   // at each
  std::vector<double> wall_seconds;       // cumulative, at each
};

// `observed_percent_by_step`: one value per `history` entry (episode_truth.h), or none
// when the map was never tied to the world (then 0 at every step); throws InputError
// for any other length.
CoverageCurve coverageByCommittedStep(const std::vector<StepRecord>& history,
                                      const std::vector<double>& observed_percent_by_step);

}  // namespace valerant
