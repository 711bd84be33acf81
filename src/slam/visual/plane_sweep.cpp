#include "valerant/slam/visual/plane_sweep.h"

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <algorithm>

#include "valerant/common/error.h"
#include "valerant/slam/visual/pinhole.h"

namespace valerant::visual {
namespace {

// Homography taking reference pixels to source pixels for the plane z = 1 / rho of the
// reference camera: K (R + t rho e_z^T) K^-1.
Eigen::Matrix3d planeHomography(const Eigen::Matrix3d& kk, const Eigen::Isometry3d& ref_to_src, double rho) {
  Eigen::Matrix3d m = ref_to_src.linear();
  m.col(2) += ref_to_src.translation() * rho;
  return kk * m * kk.inverse();
}

// Adds min(|ref - src(H x)|, truncation) to `sum` for every reference pixel x, with
// bilinear sampling; pixels mapping outside the source add the truncation. Written by
// hand because cv::warpPerspective + absdiff + min + add took 4x longer per plane (it
// builds a full remap table per call), and 128 warps per frame are the whole budget.
void addWarpedDifference(const cv::Mat& ref, const cv::Mat& src, const Eigen::Matrix3d& h, float truncation,
                         cv::Mat& sum) {
  const int w = ref.cols, rows = ref.rows;
  const float max_x = static_cast<float>(src.cols - 1), max_y = static_cast<float>(src.rows - 1);
  const size_t step = src.step1();
  const float h00 = static_cast<float>(h(0, 0)), h10 = static_cast<float>(h(1, 0)), h20 = static_cast<float>(h(2, 0));
  for (int y = 0; y < rows; ++y) {
    const float* r = ref.ptr<float>(y);
    float* out = sum.ptr<float>(y);
    const float nx0 = static_cast<float>(h(0, 1) * y + h(0, 2)), ny0 = static_cast<float>(h(1, 1) * y + h(1, 2)),
                nz0 = static_cast<float>(h(2, 1) * y + h(2, 2));
    for (int x = 0; x < w; ++x) {
      const float nz = nz0 + h20 * x;
      float cost = truncation;
      if (nz > 0) {
        const float inv = 1.f / nz;
        const float u = (nx0 + h00 * x) * inv, v = (ny0 + h10 * x) * inv;
        if (u >= 0 && v >= 0 && u < max_x && v < max_y) {
          const int u0 = static_cast<int>(u), v0 = static_cast<int>(v);
          const float a = u - u0, b = v - v0;
          const float* p = src.ptr<float>(v0) + u0;
          const float top = p[0] + a * (p[1] - p[0]), bottom = p[step] + a * (p[step + 1] - p[step]);
          cost = std::min(std::abs(r[x] - (top + b * (bottom - top))), truncation);
        }
      }
      out[x] += cost;
    }
  }
}

// Largest disparity, over a few border pixels and the sources, between the planes at
// infinity and at 1 / rho_max.
double maxDisparity(const Eigen::Matrix3d& kk, const std::vector<Eigen::Isometry3d>& ref_to_src, double rho_max,
                    const cv::Size& size) {
  double out = 0;
  const double w = size.width - 1, h = size.height - 1;
  for (const Eigen::Isometry3d& t : ref_to_src) {
    const Eigen::Matrix3d far = planeHomography(kk, t, 0), near = planeHomography(kk, t, rho_max);
    for (const Eigen::Vector3d& x : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(w, 0, 1), Eigen::Vector3d(0, h, 1),
                                     Eigen::Vector3d(w, h, 1), Eigen::Vector3d(w / 2, 0, 1), Eigen::Vector3d(w / 2, h, 1),
                                     Eigen::Vector3d(0, h / 2, 1), Eigen::Vector3d(w, h / 2, 1)}) {
      const Eigen::Vector3d a = far * x, b = near * x;
      if (a.z() <= 0 || b.z() <= 0) continue;
      out = std::max(out, (a.hnormalized() - b.hnormalized()).norm());
    }
  }
  return out;
}

}  // namespace

cv::Mat sweepImage(const cv::Mat& grey, const PlaneSweepParams& params) {
  cv::Mat small, mean, mean_sq, out;
  cv::resize(grey, small, cv::Size(grey.cols / params.downsample, grey.rows / params.downsample), 0, 0,
             cv::INTER_AREA);
  small.convertTo(small, CV_32F);
  const cv::Size window(params.normalise_window_px, params.normalise_window_px);
  cv::boxFilter(small, mean, CV_32F, window, cv::Point(-1, -1), true, cv::BORDER_REFLECT);
  cv::boxFilter(small.mul(small), mean_sq, CV_32F, window, cv::Point(-1, -1), true, cv::BORDER_REFLECT);
  cv::Mat contrast;
  cv::sqrt(cv::max(mean_sq - mean.mul(mean), 0.0), contrast);
  cv::divide(small - mean, contrast + params.contrast_floor, out);
  return out;
}

SweepDepth planeSweep(const SweepView& reference, const std::vector<SweepView>& sources,
                      const CameraIntrinsics& k, double near, const PlaneSweepParams& params) {
  if (sources.empty()) throw InputError("plane sweep", "needs at least one source view");
  if (!(near > 0)) throw InputError("plane sweep", "nearest depth must be positive");
  const cv::Size size = reference.image.size();
  const Eigen::Matrix3d kk = eigenCameraMatrix(k);
  std::vector<Eigen::Isometry3d> ref_to_src;
  for (const SweepView& s : sources) ref_to_src.push_back(s.camera_to_map.inverse() * reference.camera_to_map);
  const double rho_max = 1.0 / near;
  const int n = std::clamp(static_cast<int>(std::ceil(maxDisparity(kk, ref_to_src, rho_max, size) / params.plane_step_px)),
                           params.min_planes, params.max_planes);
  const double rho_step = rho_max / (n - 1);

  const cv::Size window(params.window_px, params.window_px);
  const double per_view = 1.0 / static_cast<double>(sources.size());
  const float truncation = static_cast<float>(params.truncation);
  std::vector<cv::Mat> cost(n);
  cv::Mat sum(size, CV_32F);
  for (int i = 0; i < n; ++i) {
    sum.setTo(0);
    for (size_t s = 0; s < sources.size(); ++s)
      addWarpedDifference(reference.image, sources[s].image, planeHomography(kk, ref_to_src[s], i * rho_step),
                          truncation, sum);
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
