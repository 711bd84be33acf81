#include "valerant/explore/keyframe_features.h"

#include <cmath>
#include <limits>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "valerant/common/error.h"

namespace valerant {
namespace {

constexpr int kDepthSearchPx = 2;
constexpr int kOrbPatchPx = 19;  // the relocaliser's: the default 31 drops a 31-pixel border at 320x240

}  // namespace

size_t KeyframeFeatures::withDepth() const {
  size_t n = 0;
  for (const auto& p : points) n += std::isfinite(p.z());
  return n;
}

KeyframeFeatures describeKeyframe(const cv::Mat& rgb, const KeyframeCloud& cloud, const CameraIntrinsics& k,
                                  const LoopClosureConfig& config) {
  if (rgb.type() != CV_8UC3 || rgb.cols != k.width || rgb.rows != k.height)
    throw InputError("keyframe " + std::to_string(cloud.keyframe) + " image",
                     "expected " + std::to_string(k.width) + "x" + std::to_string(k.height) + " RGB");
  // The cloud as a depth image of its own camera: the nearest point per pixel.
  cv::Mat depth(rgb.size(), CV_32F, cv::Scalar(std::numeric_limits<float>::infinity()));
  const Eigen::Isometry3d map_to_camera = cloud.camera_to_map.inverse();
  for (const CloudPoint& p : cloud.points) {
    const Eigen::Vector3d c = map_to_camera * p.position.cast<double>();
    if (!(c.z() > 0)) continue;
    const int u = static_cast<int>(std::lround(k.fx * c.x() / c.z() + k.cx));
    const int v = static_cast<int>(std::lround(k.fy * c.y() / c.z() + k.cy));
    if (u < 0 || v < 0 || u >= rgb.cols || v >= rgb.rows) continue;
    float& d = depth.at<float>(v, u);
    d = std::min(d, static_cast<float>(c.z()));
  }

  cv::Mat grey;
  cv::cvtColor(rgb, grey, cv::COLOR_RGB2GRAY);
  auto orb = cv::ORB::create(config.features, 1.2f, 4, kOrbPatchPx, 0, 2, cv::ORB::HARRIS_SCORE, kOrbPatchPx);
  std::vector<cv::KeyPoint> keypoints;
  KeyframeFeatures out;
  orb->detectAndCompute(grey, cv::noArray(), keypoints, out.descriptors);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (const cv::KeyPoint& kp : keypoints) {
    out.pixels.push_back(kp.pt);
    // The feature's own ray at the depth of the nearest cloud pixel.
    Eigen::Vector3f point(nan, nan, nan);
    int best = std::numeric_limits<int>::max();
    const int u0 = static_cast<int>(std::lround(kp.pt.x)), v0 = static_cast<int>(std::lround(kp.pt.y));
    for (int v = std::max(0, v0 - kDepthSearchPx); v <= std::min(rgb.rows - 1, v0 + kDepthSearchPx); ++v)
      for (int u = std::max(0, u0 - kDepthSearchPx); u <= std::min(rgb.cols - 1, u0 + kDepthSearchPx); ++u) {
        const int d2 = (u - u0) * (u - u0) + (v - v0) * (v - v0);
        if (std::isfinite(depth.at<float>(v, u)) && d2 < best) {
          best = d2;
          const float z = depth.at<float>(v, u);
          point = Eigen::Vector3f(z * (kp.pt.x - k.cx) / k.fx, z * (kp.pt.y - k.cy) / k.fy, z);
        }
      }
    out.points.push_back(point);
  }
  return out;
}

}  // namespace valerant
