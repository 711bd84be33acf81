#pragma once
// The step-aware body cylinder of eq. 6 [ours] (collision.step_height > 0): a body that
// climbs steps. The paper's cylinder stands on the floor, so a stair's riser (0.32 eye
// heights in Quake III) inside eta_low..eta_high is a wall and no staircase is ever
// climbed. Here the cylinder stands on a support height f followed along the samples,
// with s = step_height and D_i the body disc of sample i:
//   f_0 = 0 (the floor under the branch's start);
//   blocked_i = some p in D_i has f_{i-1} + s < h(p) <= f_{i-1} + eta_high;
//   blocked_i:  count_i = #{p in D_i : f_{i-1} + eta_low <= h(p) <= f_{i-1} + eta_high},
//               f_i = f_{i-1};
//   otherwise:  count_i = 0,
//               f_i = the highest h(p) <= f_{i-1} + s in D_i (f_{i-1} if there is none);
// collision from count_i exactly as in the paper (N_occ at two consecutive samples, or
// N_imm at one). Where everything at body level in the disc lies within a step of the
// support (a riser, a tread, a ramp, the floor below a drop: f may fall as well as rise)
// the body steps onto its top; where anything rises above the step (a wall, a ledge
// taller than a step) the disc is counted as the paper counts it, over the support, so a
// wall met on the floor gives the paper's counts exactly. A face taller than a step
// enters the disc at all its heights at once, so its lower part never lifts the body.
// On a staircase the risers enter the disc one at a time (a tread deeper than the sample
// spacing), each within a step of the tread before. Heights h(p) must share one datum
// along the branch (branch_check.h: the branch's first floor), else f is not
// comparable between points.
#include <vector>

#include "valerant/config/config.h"
#include "valerant/explore/point_cloud_collision.h"
#include "valerant/geometry/floor_plane.h"

namespace valerant {

struct SteppedCounts {
  std::vector<int> counts;      // count_i
  std::vector<double> support;  // f_i: the support after sample i
};

// `radius`: the body radius (normalised by each sample's camera height), as for
// bodyCylinderCounts; `config.step_height` must be > 0. The points within a sample's
// disc come from a BodyPointIndex (exactly the brute-force set), not from a pass over
// all points: with oracle depth a branch holds ~10^6 of them.
SteppedCounts steppedBodyCounts(const std::vector<HeightedPoint>& points, const std::vector<FloorPlane>& samples,
                                const CollisionConfig& config, double radius);
// The same at each of `radii` (one index for all): result[r].
std::vector<SteppedCounts> steppedBodyCounts(const std::vector<HeightedPoint>& points,
                                             const std::vector<FloorPlane>& samples, const CollisionConfig& config,
                                             const std::vector<double>& radii);

}  // namespace valerant
