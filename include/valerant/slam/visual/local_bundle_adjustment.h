#pragma once
// Local bundle adjustment (Ceres): the poses of a window of recent keyframes and every
// point they observe are refined by minimising Huber-robust reprojection errors.
// Keyframes outside the window that also observe those points enter with fixed poses,
// and fix the gauge (position, orientation and the arbitrary monocular scale).
#include <Eigen/Geometry>
#include <map>
#include <set>
#include <vector>

#include "valerant/common/camera.h"
#include "valerant/slam/visual/slam_map.h"
#include "valerant/config/visual_slam_config.h"

namespace valerant::visual {

struct BundleAdjustmentResult {
  std::map<int, Eigen::Isometry3d> poses;   // refined camera_to_map of the free keyframes
  std::map<int, Eigen::Vector3d> points;    // refined positions of the kept points
  std::vector<int> rejected;                // points reprojecting worse than max_error_px
};

// `poses`: camera_to_map of every keyframe observing a point of `points` (by id);
// `free`: the ones to refine (the rest stay fixed, at least one must).
BundleAdjustmentResult localBundleAdjustment(const std::map<int, Eigen::Isometry3d>& poses,
                                             const std::set<int>& free,
                                             const std::map<int, const MapPoint*>& points,
                                             const CameraIntrinsics& k, const BundleAdjustmentParams& params);

}  // namespace valerant::visual
