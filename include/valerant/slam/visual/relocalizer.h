#pragma once
// Relocalisation against the keyframe map after tracking is lost (the engine's eye can
// drop metres down a ledge in one frame; a camera leaving a wall sees mapped space
// again). Every keyframe keeps upright ORB descriptors of the map points it observed;
// a lost frame's corners are described the same way, matched (Hamming, ratio test)
// against recent keyframes, and posed by RANSAC PnP. Upright: the camera never rolls,
// and orientation estimates on dark, low-contrast patches are noisy.
#include <Eigen/Geometry>
#include <optional>
#include <opencv2/core.hpp>
#include <utility>
#include <vector>

#include "valerant/common/camera.h"
#include "valerant/slam/visual/slam_map.h"
#include "valerant/config/visual_slam_config.h"

namespace valerant::visual {

// Describes the map points `points` (id, pixel) of a grey CV_8U keyframe image; points
// too close to the border for a descriptor are left out.
PointDescriptors describePoints(const cv::Mat& grey, const std::vector<std::pair<int, cv::Point2f>>& points,
                                const RelocalizerParams& params);

struct Relocalization {
  Eigen::Isometry3d camera_to_map;
  std::vector<std::pair<size_t, int>> matches;  // inliers: corner index, map point id
};

// Poses a frame from its corners (pixels of a grey CV_8U image) against the described
// keyframes; culled points are skipped. Nothing without params.min_inliers PnP inliers.
std::optional<Relocalization> relocalize(const cv::Mat& grey, const std::vector<cv::Point2f>& corners,
                                         const std::vector<const PointDescriptors*>& keyframes, const SlamMap& map,
                                         const CameraIntrinsics& k, const RelocalizerParams& params,
                                         const PnpParams& pnp);

}  // namespace valerant::visual
