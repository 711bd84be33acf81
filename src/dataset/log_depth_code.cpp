#include "valerant/dataset/log_depth_code.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "valerant/common/error.h"

namespace valerant::dataset {
namespace {

constexpr double kSteps = 65534.0;  // codes 1..65535
const double kLogMin = std::log(kMinDepthM);
const double kLogSpan = std::log(kMaxDepthM) - std::log(kMinDepthM);

}  // namespace

uint16_t encodeLogDepth(double depth_m) {
  if (!(depth_m > 0)) return 0;  // NaN (sky) and nonsense alike
  const double t = std::clamp((std::log(depth_m) - kLogMin) / kLogSpan, 0.0, 1.0);
  return static_cast<uint16_t>(1 + std::lround(t * kSteps));
}

double decodeLogDepth(uint16_t code) {
  if (code == 0) return std::numeric_limits<double>::quiet_NaN();
  return std::exp(kLogMin + (code - 1) / kSteps * kLogSpan);
}

cv::Mat encodeLogDepthImage(const cv::Mat& depth_m) {
  if (depth_m.type() != CV_32F) throw InputError("depth image", "must be CV_32F metres");
  cv::Mat codes(depth_m.size(), CV_16U);
  for (int r = 0; r < depth_m.rows; ++r)
    for (int c = 0; c < depth_m.cols; ++c) codes.at<uint16_t>(r, c) = encodeLogDepth(depth_m.at<float>(r, c));
  return codes;
}

cv::Mat decodeLogDepthImage(const cv::Mat& codes) {
  if (codes.type() != CV_16U) throw InputError("depth code image", "must be CV_16U");
  cv::Mat depth(codes.size(), CV_32F);
  for (int r = 0; r < codes.rows; ++r)
    for (int c = 0; c < codes.cols; ++c)
      depth.at<float>(r, c) = static_cast<float>(decodeLogDepth(codes.at<uint16_t>(r, c)));
  return depth;
}

}  // namespace valerant::dataset
