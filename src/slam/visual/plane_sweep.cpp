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
// hand because cv::warpPerspective + absdiff + min + add took 2-3x longer per plane (it
// builds a remap table per call), and these warps are most of the per-frame budget.
// Each row runs in three loops (coordinates, gathers, blend) so that the compiler can
// vectorise the first and the last.
void addWarpedDifference(const cv::Mat& ref, const cv::Mat& src, const Eigen::Matrix3d& h, float truncation,
                         cv::Mat& sum) {
  const int w = ref.cols;
  const float max_x = static_cast<float>(src.cols - 1) - 1e-3f, max_y = static_cast<float>(src.rows - 1) - 1e-3f;
  const int step = static_cast<int>(src.step1());
  const float* base = src.ptr<float>(0);
  const float h00 = static_cast<float>(h(0, 0)), h10 = static_cast<float>(h(1, 0)), h20 = static_cast<float>(h(2, 0));
  std::vector<float> fx(w), fy(w), p00(w), p01(w), p10(w), p11(w);
  std::vector<int> offset(w);
  std::vector<uint8_t> inside(w);
  for (int y = 0; y < ref.rows; ++y) {
    const float nx0 = static_cast<float>(h(0, 1) * y + h(0, 2)), ny0 = static_cast<float>(h(1, 1) * y + h(1, 2)),
                nz0 = static_cast<float>(h(2, 1) * y + h(2, 2));
    for (int x = 0; x < w; ++x) {
      const float xf = static_cast<float>(x), nz = nz0 + h20 * xf, inv = 1.f / nz;
      const float u = (nx0 + h00 * xf) * inv, v = (ny0 + h10 * xf) * inv;
      const bool in = nz > 0 && u >= 0 && v >= 0 && u < max_x && v < max_y;
      const float uc = in ? u : 0.f, vc = in ? v : 0.f;
      const int u0 = static_cast<int>(uc), v0 = static_cast<int>(vc);
      fx[x] = uc - static_cast<float>(u0);
      fy[x] = vc - static_cast<float>(v0);
      offset[x] = v0 * step + u0;
      inside[x] = in;
    }
    for (int x = 0; x < w; ++x) {
      const float* p = base + offset[x];
      p00[x] = p[0], p01[x] = p[1], p10[x] = p[step], p11[x] = p[step + 1];
    }
    const float* r = ref.ptr<float>(y);
    float* out = sum.ptr<float>(y);
    for (int x = 0; x < w; ++x) {
      const float top = p00[x] + fx[x] * (p01[x] - p00[x]), bottom = p10[x] + fx[x] * (p11[x] - p10[x]);
      const float d = std::min(std::abs(r[x] - (top + fy[x] * (bottom - top))), truncation);
      out[x] += inside[x] ? d : truncation;
    }
  }
}

// Per pixel, what the winner and its confidence need from the cost curve, updated one
// plane at a time so the cost volume is never stored: the best plane, its neighbours'
// costs (sub-plane parabola) and the cheapest cost at least three planes away.
class CurveTracker {
 public:
  explicit CurveTracker(size_t pixels)
      : c1_(pixels, kInf), left_(pixels, kInf), right_(pixels, kInf), before_(pixels, kInf), after_(pixels, kInf),
        lag_min_(pixels, kInf), prev1_(pixels, kInf), prev2_(pixels, kInf), prev3_(pixels, kInf), best_(pixels, 0) {}

  void add(int plane, const float* cost) {
    const size_t n = c1_.size();
    for (size_t p = 0; p < n; ++p) {
      const float c = cost[p];
      const float lag = std::min(lag_min_[p], prev3_[p]);  // min of planes 0 .. plane-3
      const bool better = c < c1_[p];
      const int best = best_[p];
      const float after = plane == best + 1 ? c : after_[p];
      const float right = plane > best + 2 ? std::min(right_[p], c) : right_[p];
      left_[p] = better ? lag : left_[p];
      before_[p] = better ? prev1_[p] : before_[p];
      after_[p] = better ? kInf : after;
      right_[p] = better ? kInf : right;
      c1_[p] = better ? c : c1_[p];
      best_[p] = better ? plane : best;
      lag_min_[p] = lag;
      prev3_[p] = prev2_[p], prev2_[p] = prev1_[p], prev1_[p] = c;
    }
  }
  int best(size_t p) const { return best_[p]; }
  float bestCost(size_t p) const { return c1_[p]; }
  float rivalCost(size_t p) const { return std::min(left_[p], right_[p]); }
  float before(size_t p) const { return before_[p]; }
  float after(size_t p) const { return after_[p]; }

 private:
  static constexpr float kInf = std::numeric_limits<float>::infinity();
  std::vector<float> c1_, left_, right_, before_, after_, lag_min_, prev1_, prev2_, prev3_;
  std::vector<int> best_;
};

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
  const float truncation = static_cast<float>(params.truncation);
  CurveTracker curve(size.area());
  cv::Mat sum(size, CV_32F), cost(size, CV_32F);
  for (int i = 0; i < n; ++i) {
    sum.setTo(0);
    for (size_t s = 0; s < sources.size(); ++s)
      addWarpedDifference(reference.image, sources[s].image, planeHomography(kk, ref_to_src[s], i * rho_step),
                          truncation, sum);
    cv::boxFilter(sum, cost, CV_32F, window, cv::Point(-1, -1), true, cv::BORDER_REPLICATE);
    curve.add(i, cost.ptr<float>(0));
  }

  SweepDepth out;
  out.depth = cv::Mat(size, CV_32F, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  out.confidence = cv::Mat(size, CV_32F, cv::Scalar(0));
  // Costs are sums over the sources: the noise floor scales with their number.
  const double noise = params.noise_level * static_cast<double>(sources.size());
  float* depth = out.depth.ptr<float>(0);
  float* confidence = out.confidence.ptr<float>(0);
  for (size_t p = 0; p < static_cast<size_t>(size.area()); ++p) {
    const int best = curve.best(p);
    if (best == 0) continue;  // at infinity: no finite depth
    const double c1 = curve.bestCost(p), a = curve.before(p), b = curve.after(p);
    double offset = 0;
    if (std::isfinite(b)) {
      const double curvature = a + b - 2.0 * c1;
      if (curvature > 0) offset = std::clamp(0.5 * (a - b) / curvature, -0.5, 0.5);
    }
    depth[p] = static_cast<float>(1.0 / ((best + offset) * rho_step));
    const double ratio = (curve.rivalCost(p) + noise) / (c1 + noise);
    confidence[p] = static_cast<float>(std::min(params.max_confidence, 1.0 + params.confidence_gain * std::log(ratio)));
  }
  return out;
}

}  // namespace valerant::visual
