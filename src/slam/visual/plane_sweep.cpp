#include "valerant/slam/visual/plane_sweep.h"

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "valerant/common/error.h"
#include "valerant/slam/visual/pinhole.h"

namespace valerant::visual {
namespace {

// Homography taking reference pixels to source pixels for the plane z = 1 / rho of the
// reference camera: K (R + t rho e_z^T) K^-1.
cv::Matx33d planeHomography(const Eigen::Matrix3d& kk, const Eigen::Isometry3d& ref_to_src, double rho) {
  Eigen::Matrix3d m = ref_to_src.linear();
  m.col(2) += ref_to_src.translation() * rho;
  const Eigen::Matrix3d h = kk * m * kk.inverse();
  cv::Matx33d out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out(r, c) = h(r, c);
  return out;
}

}  // namespace

SweepDepth planeSweep(const SweepView& reference, const std::vector<SweepView>& sources,
                      const CameraIntrinsics& k, double near, const PlaneSweepParams& params) {
  if (sources.empty()) throw InputError("plane sweep", "needs at least one source view");
  if (!(near > 0)) throw InputError("plane sweep", "nearest depth must be positive");
  const cv::Size size = reference.image.size();
  const int n = params.planes;
  const double rho_step = 1.0 / near / (n - 1);
  const Eigen::Matrix3d kk = eigenCameraMatrix(k);
  std::vector<Eigen::Isometry3d> ref_to_src;
  for (const SweepView& s : sources) ref_to_src.push_back(s.camera_to_map.inverse() * reference.camera_to_map);

  // Out-of-image samples get a value far from any grey level: truncation turns them
  // into the maximum per-pixel cost.
  const cv::Scalar outside(-1e4);
  const cv::Size window(params.window_px, params.window_px);
  const double per_view = 1.0 / static_cast<double>(sources.size());
  std::vector<cv::Mat> cost(n);
  cv::Mat warped, diff, sum;
  for (int i = 0; i < n; ++i) {
    sum = cv::Mat::zeros(size, CV_32F);
    for (size_t s = 0; s < sources.size(); ++s) {
      cv::warpPerspective(sources[s].image, warped, planeHomography(kk, ref_to_src[s], i * rho_step), size,
                          cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT, outside);
      cv::absdiff(reference.image, warped, diff);
      cv::min(diff, params.truncation, diff);
      sum += diff;
    }
    cv::boxFilter(sum, cost[i], CV_32F, window, cv::Point(-1, -1), true, cv::BORDER_REPLICATE);
    cost[i] *= per_view;
  }

  SweepDepth out;
  out.depth = cv::Mat(size, CV_32F, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  out.confidence = cv::Mat(size, CV_32F, cv::Scalar(0));
  std::vector<const float*> rows(n);
  const float noise = static_cast<float>(params.noise_level);
  for (int y = 0; y < size.height; ++y) {
    for (int i = 0; i < n; ++i) rows[i] = cost[i].ptr<float>(y);
    float* depth = out.depth.ptr<float>(y);
    float* confidence = out.confidence.ptr<float>(y);
    for (int x = 0; x < size.width; ++x) {
      int best = 0;
      float c1 = rows[0][x];
      for (int i = 1; i < n; ++i)
        if (rows[i][x] < c1) c1 = rows[i][x], best = i;
      if (best == 0) continue;  // at infinity: no finite depth
      float c2 = std::numeric_limits<float>::max();
      for (int i = 0; i < n; ++i)
        if (std::abs(i - best) > 2 && rows[i][x] < c2) c2 = rows[i][x];
      double offset = 0;
      if (best + 1 < n) {
        const double a = rows[best - 1][x], b = rows[best + 1][x], curvature = a + b - 2.0 * c1;
        if (curvature > 0) offset = std::clamp(0.5 * (a - b) / curvature, -0.5, 0.5);
      }
      depth[x] = static_cast<float>(1.0 / ((best + offset) * rho_step));
      const double ratio = (c2 + noise) / (c1 + noise);
      confidence[x] = static_cast<float>(std::min(params.max_confidence, 1.0 + params.confidence_gain * std::log(ratio)));
    }
  }
  return out;
}

}  // namespace valerant::visual
