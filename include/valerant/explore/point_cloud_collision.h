#pragma once
// Point-cloud collision, paper eq. 6: does the reconstructed geometry of a candidate
// enter a floor-normalised vertical body cylinder along its trajectory?
//   count_i = #{p : dist_perp(p, c_i) / kappa_i <= rho,  eta_low <= h(p) <= eta_high,
//                 confidence(p) >= 4}
//   collision iff count_i >= N_occ at two consecutive samples i-1, i,
//                 or count_i >= N_imm (300) at one sample (a deep penetration).
// dist_perp is measured from the body axis, the line through the camera centre c_i
// along the floor normal n_i of sample i; kappa_i = n_i.(c_i - q_i). h(p) uses the
// floor of the point's own source keyframe (eq. 5). Rotation-only candidates are
// exempt: they add no translational penetration.
// [ours] collision.step_height > 0: count_i comes from the step-aware cylinder that
// rides up the treads it steps onto (step_support.h); 0 is the paper's band above.
#include <Eigen/Core>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/geometry/floor_plane.h"

namespace valerant {

struct HeightedPoint {
  Eigen::Vector3d position;
  double h = 0;  // normalised height from its source keyframe's floor
  float confidence = 0;
};

struct PointCloudCollision {
  bool collision = false;
  int occupied_max = 0;  // largest count_i over the samples
  int sample = -1;       // first sample where the test fired
  int run_start = -1;    // first sample of the run of occupied samples that fired
};

// Whether the cylinder of eq. 6 (without steps) counts a point of height h and this
// confidence: confident and at body level, eta_low <= h <= eta_high (false for NaN h).
inline bool countedInBody(double h, float confidence, const CollisionConfig& config) {
  return confidence >= config.min_confidence && h >= config.height_low && h <= config.height_high;
}

// count_i of every sample for each body radius in `radii` (normalised, rho for eq. 6):
// result[r][i]. The points are filtered and indexed once for all radii (the branch
// check counts at rho and at the prefix clearance); stepped when config.step_height > 0.
std::vector<std::vector<int>> bodyCylinderCounts(const std::vector<HeightedPoint>& points,
                                                 const std::vector<FloorPlane>& samples,
                                                 const CollisionConfig& config, const std::vector<double>& radii);

// Eq. 6's decision from the counts at rho of every sample.
PointCloudCollision pointCloudCollisionFromCounts(const std::vector<int>& counts, const CollisionConfig& config,
                                                  bool rotation_only);

// Both steps at config.body_radius. `samples`: one floor per trajectory sample, with
// FloorPlane::c its camera centre.
PointCloudCollision detectPointCloudCollision(const std::vector<HeightedPoint>& points,
                                              const std::vector<FloorPlane>& samples,
                                              const CollisionConfig& config, bool rotation_only);

}  // namespace valerant
