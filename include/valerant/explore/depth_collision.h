#pragma once
// Depth-based collision, paper eq. 7: a frontal surface within the normalised near
// field while the estimated trajectory still advances afterwards.
//   fires iff  exists l:  Avg_ctr(depth_l) / kappa_l <= d_near
//                    and  Fwd(l, L) / kappa_l >= s_min(l) and Fwd(l, L) > 0,
//   s_min(l) = 0.085 d_fwd (L - l) / L    (l = 1..L, d_fwd normalised by eye height)
// Avg_ctr is the mean finite raw depth over the central `center_fraction` of the
// image in both directions; Fwd(l, L) is the displacement from frame l to the last
// frame L along frame l's heading (its optical axis projected on the floor plane).
// Every rollout frame is evaluated, keyframe or not. The strict Fwd > 0 keeps the
// last frame (where s_min = 0) from firing on a wall that is merely looked at.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/geometry/floor_plane.h"

namespace valerant {

// Mean of the finite positive depths in the central window; NaN when there are none.
double centralMeanDepth(const cv::Mat& depth, double center_fraction);

struct DepthSample {
  double central_depth = 0;        // centralMeanDepth of the frame (NaN: no depth)
  FloorPlane floor;                // floor at this frame, c = camera centre
  Eigen::Vector3d forward;         // optical axis in the map frame
};

struct DepthCollision {
  bool collision = false;
  int frame = -1;               // first frame (0-based) where it fired
  double min_near_ratio = 0;    // smallest Avg_ctr / kappa over all frames (diagnostics)
};

// `d_fwd_normalised`: nominal forward displacement divided by eye height (256/50).
DepthCollision detectDepthCollision(const std::vector<DepthSample>& frames, const CollisionConfig& config,
                                    double d_fwd_normalised);

}  // namespace valerant
