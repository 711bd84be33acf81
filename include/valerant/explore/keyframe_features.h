#pragma once
// What loop closure keeps of a committed keyframe to recognise its place later: ORB
// features of its image and, under each, the 3D point its own cloud puts there, in the
// keyframe's camera frame (SLAM units). Camera-frame points do not move when the pose
// graph corrects the keyframe, and a match against them gives the new camera's pose
// relative to the old one directly. A feature gets the depth of the nearest cloud point
// projected within kDepthSearchPx pixels (the visual SLAM's clouds come every 2 px, the
// oracle's every cloud_stride_px).
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "valerant/common/camera.h"
#include "valerant/config/config.h"
#include "valerant/slam/slam.h"

namespace valerant {

struct KeyframeFeatures {
  std::vector<cv::Point2f> pixels;
  cv::Mat descriptors;                  // CV_8U, one 32-byte ORB row per feature
  std::vector<Eigen::Vector3f> points;  // camera frame; NaN where the cloud has no depth
  size_t withDepth() const;
};

// `rgb`: the keyframe's CV_8UC3 image; `cloud`: its points in the SLAM frame.
KeyframeFeatures describeKeyframe(const cv::Mat& rgb, const KeyframeCloud& cloud, const CameraIntrinsics& k,
                                  const LoopClosureConfig& config);

}  // namespace valerant
