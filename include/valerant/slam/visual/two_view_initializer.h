#pragma once
// Two-view initialisation of a monocular map: essential matrix (RANSAC) and the
// cheirality-checked pose of OpenCV's recoverPose, then triangulation with per-point
// parallax and reprojection checks. The pair is not `ready` when too few points survive
// or their median parallax is too small (a rotation with little translation would
// otherwise produce a map of garbage depths); its rotation is still usable then.
#include <Eigen/Geometry>
#include <optional>
#include <opencv2/core.hpp>
#include <vector>

#include "valerant/common/camera.h"
#include "valerant/config/visual_slam_config.h"

namespace valerant::visual {

struct TwoViewResult {
  bool ready = false;                      // enough well-triangulated points to start a map
  Eigen::Isometry3d b_to_a;                // camera b in camera a's frame, |translation| = 1
  std::vector<int> indices;                // correspondences that became points
  std::vector<Eigen::Vector3d> points;     // in camera a's frame, same order as indices
  double median_parallax_deg = 0;
};

// Nothing when no essential matrix has params.min_points inliers in front of both cameras.
std::optional<TwoViewResult> initializeTwoView(const std::vector<cv::Point2f>& a,
                                               const std::vector<cv::Point2f>& b, const CameraIntrinsics& k,
                                               const TwoViewParams& params);

}  // namespace valerant::visual
