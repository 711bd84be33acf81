#pragma once
// The rotation-only motion model between two views: x_b ~ K R K^-1 x_a. It tracks a
// camera turning in place (candidates jq, lq) where nothing can be triangulated, and
// its residual measures the parallax that decides whether two-view geometry is
// worth trying.
#include <Eigen/Geometry>
#include <optional>
#include <opencv2/core.hpp>
#include <vector>

#include "valerant/common/camera.h"

namespace valerant::visual {

struct RotationEstimate {
  Eigen::Matrix3d b_from_a;       // bearing_b = b_from_a * bearing_a
  std::vector<int> inliers;       // indices into the correspondences
  double median_parallax_px = 0;  // median distance between b and the rotated a, all pairs
};

// RANSAC homography (OpenCV), projected onto SO(3) and refined on the inlier bearings
// (Kabsch via Eigen::umeyama). Nothing when fewer than `min_inliers` agree.
std::optional<RotationEstimate> estimateRotation(const std::vector<cv::Point2f>& a,
                                                 const std::vector<cv::Point2f>& b, const CameraIntrinsics& k,
                                                 double threshold_px, int min_inliers);

}  // namespace valerant::visual
