#pragma once
// Two-view triangulation of pixel correspondences between posed cameras, keeping only
// points that are in front of both cameras (cheirality), reproject within a few pixels
// and are seen under enough parallax to have a usable depth.
#include <Eigen/Geometry>
#include <optional>
#include <opencv2/core.hpp>
#include <vector>

#include "valerant/common/camera.h"

namespace valerant::visual {

struct TriangulationLimits {
  double min_parallax_deg = 1.0;
  double max_reprojection_px = 2.0;
};

struct Triangulated {
  Eigen::Vector3d position;  // map frame
  double parallax_deg = 0;
};

// One result per correspondence; empty where a check fails.
std::vector<std::optional<Triangulated>> triangulate(const Eigen::Isometry3d& a_to_map,
                                                     const Eigen::Isometry3d& b_to_map,
                                                     const std::vector<cv::Point2f>& px_a,
                                                     const std::vector<cv::Point2f>& px_b,
                                                     const CameraIntrinsics& k, const TriangulationLimits& limits);

}  // namespace valerant::visual
