#pragma once
// The clean prefix of a rejected translation ([ours], collision.prefix_commits). The
// paper commits whole rollouts, 8 m of forward motion for uw; Quake III rooms are
// rarely that deep, so from most spawns every translation is rejected and the agent
// only turns, which a monocular SLAM cannot map (docs/evaluation.md). A rejected
// translation's frames before its first unsafe frame (the first sample of the
// point-cloud run that fired, the frame where the depth test fired, the first frame
// the SLAM lost, or the first sample with N_occ points within the wider
// collision.prefix_clearance of its axis) are fine to walk, minus a margin:
//   k = max { k <= f : |c_{k-1} - c_r|_h >= margin kappa_r  and  |c_{k-1} - c_0|_h >= min_advance kappa_r }
// where f is the first unsafe frame, r the frame the obstacle is measured from (f, or
// the last tracked frame f-1 when the SLAM lost track at f), |.|_h the distance across
// the floor normal of frame r and kappa_r its camera-to-floor distance. k = 0 when no
// prefix advances far enough; k = all frames when nothing fired. A branch that only
// lost track (neither test fired) offers none (BranchCheck): a camera inside a Quake III
// brush sees through it, so a loss does not mark the obstacle. Episode judges the
// prefix as a new candidate ("uw@k"), rolled out and reconstructed afresh.
#include <vector>

#include "valerant/geometry/floor_plane.h"

namespace valerant {

// `frames`: one floor per rollout frame, FloorPlane::c its camera centre.
// `first_unsafe` < 0: nothing fired. `reference`: the frame the obstacle is measured
// from (< 0: none tracked, no prefix).
int cleanPrefixFrames(const std::vector<FloorPlane>& frames, int first_unsafe, int reference, double margin,
                      double min_advance);

}  // namespace valerant
