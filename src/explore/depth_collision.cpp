#include "valerant/explore/depth_collision.h"

#include <cmath>
#include <limits>

namespace valerant {

double centralMeanDepth(const cv::Mat& depth, double center_fraction) {
  const int w = std::max(1, static_cast<int>(std::lround(depth.cols * center_fraction)));
  const int h = std::max(1, static_cast<int>(std::lround(depth.rows * center_fraction)));
  const cv::Mat window = depth(cv::Rect((depth.cols - w) / 2, (depth.rows - h) / 2, w, h));
  double sum = 0;
  int count = 0;
  for (int r = 0; r < window.rows; ++r) {
    const float* row = window.ptr<float>(r);
    for (int c = 0; c < window.cols; ++c) {
      if (std::isfinite(row[c]) && row[c] > 0) {
        sum += row[c];
        ++count;
      }
    }
  }
  return count ? sum / count : std::numeric_limits<double>::quiet_NaN();
}

DepthCollision detectDepthCollision(const std::vector<DepthSample>& frames, const CollisionConfig& config,
                                    double d_fwd_normalised) {
  DepthCollision result;
  result.min_near_ratio = std::numeric_limits<double>::infinity();
  const size_t L = frames.size();
  if (L == 0) return result;
  const Eigen::Vector3d last = frames.back().floor.c;
  for (size_t i = 0; i < L; ++i) {
    const DepthSample& f = frames[i];
    const double kappa = f.floor.cameraHeight();
    if (!(kappa > 0) || !std::isfinite(f.central_depth)) continue;
    const double near_ratio = f.central_depth / kappa;
    result.min_near_ratio = std::min(result.min_near_ratio, near_ratio);
    Eigen::Vector3d heading = f.forward - f.forward.dot(f.floor.n) * f.floor.n;
    if (heading.norm() < 1e-9) continue;  // looking straight down: no heading
    heading.normalize();
    const double fwd = (last - f.floor.c).dot(heading);
    const double l = static_cast<double>(i + 1);
    const double s_min = config.s_min_coefficient * d_fwd_normalised * (L - l) / L;
    if (!result.collision && near_ratio <= config.d_near && fwd > 0 && fwd / kappa >= s_min) {
      result.collision = true;
      result.frame = static_cast<int>(i);
    }
  }
  return result;
}

}  // namespace valerant
