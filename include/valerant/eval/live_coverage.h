#pragma once
// The share of the reachable floor an episode's map observes, kept current step by step
// for progress lines (engine world only). Counting it from scratch after every step
// grows with the square of the steps; here a step costs the points of its new keyframes.
// The map-to-world alignment (episode_truth.h alignEpisode) is refitted, and every
// keyframe counted again, only when the map has doubled since the last fit or a rewind
// dropped a counted keyframe: the work stays linear in the map, and between fits the
// figure uses the last fit (exact for the oracle SLAM, whose alignment is fixed).
// report.json's figures come from evaluateEpisodeTruth with the final alignment.
#include <cstdint>
#include <set>

#include "valerant/eval/episode_truth.h"

namespace valerant {

class LiveCoverage {
 public:
  explicit LiveCoverage(const quake3::ReachableFloor& reachable);
  // Brings the count up to `episode`'s map; returns the percent of the reachable floor
  // observed (0 before the map can be tied to the world).
  double update(const Episode& episode);
  int refits() const { return refits_; }  // full recounts so far

 private:
  ReachableCells cells_;
  EpisodeAlignment alignment_;
  std::set<ReachableCells::CellStorey> observed_;
  size_t counted_ = 0;          // keyframes counted under alignment_
  uint64_t last_counted_id_ = 0;  // id of the last one (a rewind that dropped it is seen here)
  size_t fitted_at_ = 0;        // keyframes when alignment_ was fitted
  int refits_ = 0;
};

}  // namespace valerant
