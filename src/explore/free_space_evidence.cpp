#include "valerant/explore/free_space_evidence.h"

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "valerant/common/error.h"
#include "valerant/slam/visual/pinhole.h"

namespace valerant {

FreeSpaceEvidence freeSpaceEvidence(const Eigen::Vector3d& p, const std::vector<DepthView>& views,
                                    const CameraIntrinsics& k, double tau) {
  FreeSpaceEvidence e;
  for (const DepthView& v : views) {
    const Eigen::Vector3d x = v.map_to_camera * p;
    if (!(x.z() > 0)) continue;
    const Eigen::Vector2d px = visual::project(k, x);
    if (!(px.x() >= 0 && px.y() >= 0 && px.x() < v.depth.cols && px.y() < v.depth.rows)) continue;
    const float d = v.depth.at<float>(static_cast<int>(px.y()), static_cast<int>(px.x()));
    if (!std::isfinite(d)) continue;
    if (d > (1 + tau) * x.z())
      ++e.through;
    else if (std::abs(d - x.z()) <= tau * x.z())
      ++e.support;
  }
  return e;
}

DepthView depthViewOf(const Eigen::Isometry3d& camera_to_map, const cv::Mat& depth, const cv::Mat& confidence,
                      double min_confidence, int shrink) {
  if (depth.type() != CV_32FC1 || confidence.type() != CV_32FC1 || depth.size() != confidence.size())
    throw InputError("depth view", "depth and confidence must be CV_32F images of one size");
  DepthView v;
  v.map_to_camera = camera_to_map.inverse();
  cv::Mat known = depth.clone();
  known.setTo(std::numeric_limits<float>::quiet_NaN(), confidence < min_confidence);
  if (shrink > 1)
    cv::resize(known, v.depth, cv::Size(depth.cols / shrink, depth.rows / shrink), 0, 0, cv::INTER_NEAREST);
  else
    v.depth = known;
  return v;
}

DepthView depthViewOfCloud(const KeyframeCloud& keyframe, const CameraIntrinsics& view, double min_confidence) {
  if (view.width <= 0 || view.height <= 0) throw InputError("depth view", "the view's intrinsics have no size");
  DepthView v;
  v.map_to_camera = keyframe.camera_to_map.inverse();
  v.depth = cv::Mat(view.height, view.width, CV_32F, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  for (const CloudPoint& p : keyframe.points) {
    if (p.confidence < min_confidence) continue;
    const Eigen::Vector3d x = v.map_to_camera * p.position.cast<double>();
    if (!(x.z() > 0)) continue;
    const Eigen::Vector2d px = visual::project(view, x);
    if (!(px.x() >= 0 && px.y() >= 0 && px.x() < view.width && px.y() < view.height)) continue;
    float& d = v.depth.at<float>(static_cast<int>(px.y()), static_cast<int>(px.x()));
    if (!(d <= x.z())) d = static_cast<float>(x.z());  // NaN or farther: the nearer point is what the view saw
  }
  return v;
}

}  // namespace valerant
