#pragma once
// Camera pose from 2D-3D correspondences against the local map: RANSAC over EPnP
// minimal sets, then Levenberg-Marquardt refinement on the inliers.
#include <Eigen/Geometry>
#include <optional>
#include <opencv2/core.hpp>
#include <vector>

#include "valerant/common/camera.h"
#include "valerant/config/visual_slam_config.h"

namespace valerant::visual {

struct PnpResult {
  Eigen::Isometry3d camera_to_map;
  std::vector<int> inliers;  // indices into the correspondences
};

// Nothing when RANSAC fails or fewer than params.min_inliers agree. RANSAC draws from
// OpenCV's per-thread RNG: the caller seeds it for reproducible branches.
std::optional<PnpResult> solvePnp(const std::vector<cv::Point3f>& points, const std::vector<cv::Point2f>& pixels,
                                  const CameraIntrinsics& k, const PnpParams& params);

}  // namespace valerant::visual
