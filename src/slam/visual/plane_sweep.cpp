#include "valerant/slam/visual/plane_sweep.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "valerant/common/error.h"
#include "valerant/slam/visual/box_mean.h"
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

// A source image re-sampled with the reference camera's orientation (once per frame,
// by cv::warpPerspective with the homography at infinity K R K^-1), on a canvas padded
// by `margin` pixels. For the plane z = 1 / rho of the reference, reference pixel x then
// samples it at (x + rho e_xy) / (1 + rho e_z) with e = K R^T t: per plane a uniform
// scale about the epipole, constant along each row in y.
struct CompensatedSource {
  cv::Mat canvas;  // CV_32F
  Eigen::Vector3d epipole;
  int margin = 0;
};

// Canvas value outside the source, far from any normalised grey level (locally
// normalised images stay within a few units). Interpolation, cubic ringing included,
// spreads it into neighbours: any difference above kImplausible marks the sample as
// touching the outside.
constexpr float kOutside = -1e4f;
constexpr float kImplausible = 100.f;
// Cost of a sample outside a source. A pixel whose window holds one is not scored for
// that plane at all: a fixed penalty would make the planes that keep it inside the
// source look better than the rest, a confident false depth.
constexpr float kInvalid = 1e5f;

CompensatedSource compensate(const SweepView& source, const Eigen::Matrix3d& kk, const Eigen::Isometry3d& ref_to_src,
                             const cv::Size& size, int margin) {
  CompensatedSource c;
  c.margin = margin;
  c.epipole = kk * ref_to_src.linear().transpose() * ref_to_src.translation();
  Eigen::Matrix3d canvas_to_ref = Eigen::Matrix3d::Identity();
  canvas_to_ref(0, 2) = canvas_to_ref(1, 2) = -margin;
  const Eigen::Matrix3d m = kk * ref_to_src.linear() * kk.inverse() * canvas_to_ref;
  cv::Matx33d h;
  for (int r = 0; r < 3; ++r)
    for (int col = 0; col < 3; ++col) h(r, col) = m(r, col);
  cv::warpPerspective(source.image, c.canvas, h, cv::Size(size.width + 2 * margin, size.height + 2 * margin),
                      cv::INTER_CUBIC | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT, cv::Scalar(kOutside));
  return c;
}

// Adds min(|ref - source(plane rho)|, truncation) to `sum` for every reference pixel
// (kInvalid outside the source), by linear interpolation of a vertically blended
// canvas row. No OpenCV call samples a per-plane affine map and takes the truncated
// difference in one pass, and these samples (planes x sources x pixels) are most of
// the frame's budget: the row loop is sweep_kernels.h's.
void addPlaneDifference(const cv::Mat& ref, const CompensatedSource& src, double rho, float truncation,
                        cv::Mat& sum, std::vector<float>& row, SweepIsa isa) {
  const double w = 1.0 + rho * src.epipole.z();
  if (w <= 1e-6) {  // the plane is behind the source camera
    sum += kInvalid;
    return;
  }
  const float scale = static_cast<float>(1.0 / w);
  const float shift_y = static_cast<float>(rho * src.epipole.y() / w) + static_cast<float>(src.margin);
  const int cols = src.canvas.cols;
  RowSampling sampling;
  sampling.scale = scale;
  sampling.shift = static_cast<float>(rho * src.epipole.x() / w) + static_cast<float>(src.margin);
  sampling.max_u = static_cast<float>(cols - 1) - 1e-3f;
  sampling.truncation = truncation;
  sampling.implausible = kImplausible;
  sampling.invalid = kInvalid;
  const float max_v = static_cast<float>(src.canvas.rows - 1) - 1e-3f;
  row.resize(cols);
  for (int y = 0; y < ref.rows; ++y) {
    float* out = sum.ptr<float>(y);
    const float v = scale * static_cast<float>(y) + shift_y;
    if (!(v >= 0 && v < max_v)) {
      for (int x = 0; x < ref.cols; ++x) out[x] += kInvalid;
      continue;
    }
    const int v0 = static_cast<int>(v);
    const float fy = v - static_cast<float>(v0);
    const float* top = src.canvas.ptr<float>(v0);
    const float* bottom = src.canvas.ptr<float>(v0 + 1);
    blendRows(top, bottom, fy, cols, row.data(), isa);
    addTruncatedDifferences(ref.ptr<float>(y), row.data(), ref.cols, sampling, out, isa);
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

  const float truncation = static_cast<float>(params.truncation);
  const SweepIsa isa = params.simd ? fastestSweepIsa() : SweepIsa::kPortable;
  CostCurveTracker curve(size.area(), isa);
  // Padding keeps samples that leave the reference's view but not the source's.
  const int margin = std::max(size.width, size.height) / 8;
  std::vector<CompensatedSource> compensated;
  for (size_t s = 0; s < sources.size(); ++s)
    compensated.push_back(compensate(sources[s], kk, ref_to_src[s], size, margin));
  cv::Mat sum(size, CV_32F), cost(size, CV_32F);
  std::vector<float> row;
  BoxMean window_mean(params.window_px, isa);
  for (int i = 0; i < n; ++i) {
    sum.setTo(0);
    for (const CompensatedSource& c : compensated)
      addPlaneDifference(reference.image, c, i * rho_step, truncation, sum, row, isa);
    window_mean.apply(sum, cost);
    curve.add(i, cost.ptr<float>(0), kInvalid / static_cast<float>(params.window_px * params.window_px));
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
    const double c1 = curve.bestCost(p), c2 = curve.rivalCost(p), a = curve.before(p), b = curve.after(p);
    if (best == 0 || !std::isfinite(c1)) continue;  // at infinity, or never inside every source
    double offset = 0;
    if (std::isfinite(a) && std::isfinite(b)) {
      const double curvature = a + b - 2.0 * c1;
      if (curvature > 0) offset = std::clamp(0.5 * (a - b) / curvature, -0.5, 0.5);
    }
    // Too close to infinity to be a measurement: the one-plane bracket spans more
    // than +-1 / (2 min_plane) of the depth (and such points blow up the map extent).
    if (best + offset < params.min_plane) continue;
    depth[p] = static_cast<float>(1.0 / ((best + offset) * rho_step));
    // Without a scored rival the depth is unsupported, not certain.
    const double ratio = std::isfinite(c2) ? (c2 + noise) / (c1 + noise) : 1.0;
    confidence[p] = static_cast<float>(std::min(params.max_confidence, 1.0 + params.confidence_gain * std::log(ratio)));
  }
  return out;
}

}  // namespace valerant::visual
