#pragma once
// The step-aware body cylinder of eq. 6 [ours] (collision.step_height > 0): a body that
// climbs steps. The paper's cylinder stands on the floor, so a stair's riser (0.32 eye
// heights in Quake III) inside eta_low..eta_high is a wall and no staircase is ever
// climbed. Here the cylinder stands on a support height f followed along the samples,
// with s = step_height, D_i the body disc of sample i and e_i = h(c_i) - 1 the floor
// under the eye (the camera c_i stands one eye height over its feet), clamp_i(x) =
// min(max(x, e_i - s), e_i + s):
//   f_{-1} = 0 (the floor under the branch's start);
//   g_i = clamp_i(f_{i-1}) (the body stands within a step of the eye's floor);
//   blocked_i = some p in D_i has g_i + s < h(p) <= g_i + eta_high;
//   blocked_i:  count_i = #{p in D_i : g_i + eta_low <= h(p) <= g_i + eta_high},
//               f_i = g_i (with collision.step_count = above_step [ours]:
//               count_i = #{p in D_i : g_i + s < h(p) <= g_i + eta_high}, only what the
//               body cannot step over: the visual depth reads a few per cent of near
//               floor 20 to 45 % short, and such a floor point sits 0.2 to 0.45 eye
//               heights up, within a step, where one stray point over the step made the
//               band count it as wall; no gain in episodes, docs/pockets.md, "Floor
//               within a step");
//   otherwise:  count_i = 0,
//               f_i = clamp_i(the highest h(p) <= g_i + s in D_i (g_i if there is none));
// and, with collision.climb_lag L > 0, u_i = u_{i-1} + 1 where f_i > e_i + eta_low (u_i = 0
// elsewhere, u_{-1} = 0): where u_i > L the body has stood over the eye's floor for more
// than L samples, the world did not lift the camera onto what the body climbed (a ledge
// over the player's step: the engine keeps the feet on the floor and the hull sinks into
// the ledge), and count_i = #{p in D_i : e_i + eta_low <= h(p) <= e_i + eta_high}, the
// paper's count over the eye's floor; collision from count_i exactly as in the paper
// (N_occ at two consecutive samples, or N_imm at one). Where everything at body level in
// the disc lies within a step of the support (a riser, a tread, a ramp, the floor below
// a drop: f may fall as well as rise) the body steps onto its top; where anything rises
// above the step (a wall, a ledge taller than a step) the disc is counted as the paper
// counts it, over the support, so a wall met on the floor gives the paper's counts
// exactly. A face taller than a step enters the disc at all its heights at once, so its
// lower part never lifts the body. On a staircase the risers enter the disc one at a
// time (a tread deeper than the sample spacing), each within a step of the tread before,
// while the eye climbs behind them.
// The clamp keeps the body where the eye is: without it a face seen from a tilted datum
// (a floor fitted 19 degrees off) rose a little per sample like a ramp, f climbed it 4 eye
// heights over a level camera, the wall above the eye's feet passed over the body's head
// and eq. 6 counted 0 while the camera walked through the wall and out of the level
// (oa_dm3 spawn 1, 150 steps; docs/pockets.md, "The body within a step of the eye").
// The climb lag: a camera is carried by its body, so where the body climbs the eye
// follows within a few samples (in Quake III at once: the hull box and the disc reach a
// riser together, and the engine lifts the camera onto the highest floor under the box).
// Without it a 21-unit ledge, over the engine's 18-unit step but within s = 0.45, was
// climbed by the body while the camera walked on with its feet 21 units deep in the slab
// for 140 steps (hydronex spawn 1; docs/pockets.md).
// Heights h(p) must share one datum along the branch, the first sample's floor
// (branch_check.h: the branch's first floor), else f is not comparable between points.
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

// e_i for every sample: the height of the floor under sample i's eye over the first
// sample's floor, in that floor's camera heights (h(c_i) - 1; 0 for the first sample).
std::vector<double> eyeSupports(const std::vector<FloorPlane>& samples);
// clamp_i: `support` kept within `step_height` of `eye_support` (unchanged where the
// eye's height is not finite).
double withinAStepOfTheEye(double support, double eye_support, double step_height);

}  // namespace valerant
