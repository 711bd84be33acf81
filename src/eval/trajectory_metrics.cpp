#include "valerant/eval/trajectory_metrics.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "valerant/common/error.h"

namespace valerant {
namespace {

// Spread below which the estimated centres count as not moving (rotation in place).
constexpr double kMinSpread = 1e-9;

Eigen::Matrix3Xd columns(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Matrix3Xd m(3, points.size());
  for (size_t i = 0; i < points.size(); ++i) m.col(i) = points[i];
  return m;
}

double spread(const Eigen::Matrix3Xd& m) { return (m.colwise() - m.rowwise().mean()).squaredNorm() / m.cols(); }

// Rotation A minimising sum ||A R_est,i - R_truth,i||_F (chordal L2 mean).
Eigen::Matrix3d bestRotation(const std::vector<Eigen::Isometry3d>& estimate, const std::vector<Eigen::Isometry3d>& truth) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < estimate.size(); ++i) m += truth[i].linear() * estimate[i].linear().transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1 : 1;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

// The centres' second principal axis carries less than this share of the first's
// extent: a line, whose roll positions cannot fix.
constexpr double kCollinearRatio = 0.1;

bool collinear(const Eigen::Matrix3Xd& m) {
  const Eigen::Matrix3Xd centred = m.colwise() - m.rowwise().mean();
  const Eigen::Vector3d s = Eigen::JacobiSVD<Eigen::Matrix3Xd>(centred).singularValues();
  return s(1) < kCollinearRatio * s(0);
}

// alignSim3's preconditions: matched lengths, at least 3 points, a spread estimate.
void requireAlignable(const std::vector<Eigen::Vector3d>& estimate, const std::vector<Eigen::Vector3d>& truth) {
  if (estimate.size() != truth.size())
    throw InputError("Sim(3) alignment", "estimate has " + std::to_string(estimate.size()) + " points, truth " +
                                             std::to_string(truth.size()));
  if (estimate.size() < 3) throw InputError("Sim(3) alignment", "needs at least 3 matched points");
  if (spread(columns(estimate)) < kMinSpread) throw InputError("Sim(3) alignment", "estimated points do not spread");
}

}  // namespace

std::optional<Sim3> alignSim3ByOrientation(const std::vector<Eigen::Isometry3d>& estimate,
                                           const std::vector<Eigen::Isometry3d>& truth) {
  std::vector<Eigen::Vector3d> est, gt;
  for (const auto& p : estimate) est.push_back(p.translation());
  for (const auto& p : truth) gt.push_back(p.translation());
  requireAlignable(est, gt);
  Sim3 out;
  out.rotation = bestRotation(estimate, truth);
  const Eigen::Matrix3Xd src = columns(est), dst = columns(gt);
  const Eigen::Vector3d src_mean = src.rowwise().mean(), dst_mean = dst.rowwise().mean();
  const Eigen::Matrix3Xd a = out.rotation * (src.colwise() - src_mean), b = dst.colwise() - dst_mean;
  out.scale = (a.cwiseProduct(b)).sum() / a.squaredNorm();
  if (!(out.scale > 0)) return std::nullopt;
  out.translation = dst_mean - out.scale * (out.rotation * src_mean);
  return out;
}

Sim3 alignSim3(const std::vector<Eigen::Vector3d>& estimate, const std::vector<Eigen::Vector3d>& truth) {
  requireAlignable(estimate, truth);
  const Eigen::Matrix3Xd src = columns(estimate), dst = columns(truth);
  const Eigen::Matrix4d t = Eigen::umeyama(src, dst, true);
  Sim3 out;
  out.scale = t.topLeftCorner<3, 3>().col(0).norm();
  out.rotation = t.topLeftCorner<3, 3>() / out.scale;
  out.translation = t.topRightCorner<3, 1>();
  return out;
}

TrajectoryError trajectoryError(const std::vector<Eigen::Isometry3d>& estimate,
                                const std::vector<Eigen::Isometry3d>& truth) {
  if (estimate.size() != truth.size() || estimate.empty())
    throw InputError("trajectory error", "needs equally long non-empty trajectories (estimate " +
                                             std::to_string(estimate.size()) + ", truth " +
                                             std::to_string(truth.size()) + ")");
  TrajectoryError e;
  e.frames = static_cast<int>(estimate.size());
  std::vector<Eigen::Vector3d> est, gt;
  for (size_t i = 0; i < estimate.size(); ++i) {
    est.push_back(estimate[i].translation());
    gt.push_back(truth[i].translation());
    if (i > 0) e.path_length += (gt[i] - gt[i - 1]).norm();
  }
  const Eigen::Matrix3Xd src = columns(est);
  e.aligned = est.size() >= 3 && spread(src) >= kMinSpread;
  double sum = 0;
  if (e.aligned) {
    const std::optional<Sim3> by_orientation =
        collinear(src) ? alignSim3ByOrientation(estimate, truth) : std::nullopt;
    e.alignment = by_orientation ? *by_orientation : alignSim3(est, gt);
    for (size_t i = 0; i < est.size(); ++i) sum += (e.alignment.apply(est[i]) - gt[i]).squaredNorm();
  } else {
    // A camera that never moved maps to one point at best: the truth's centroid.
    const Eigen::Matrix3Xd dst = columns(gt);
    sum = spread(dst) * static_cast<double>(gt.size());
  }
  e.ate_rmse = std::sqrt(sum / static_cast<double>(est.size()));
  e.ate_percent = e.path_length > 1e-9 ? 100.0 * e.ate_rmse / e.path_length : std::numeric_limits<double>::quiet_NaN();

  const Eigen::Matrix3d a = bestRotation(estimate, truth);
  double rot = 0;
  for (size_t i = 0; i < estimate.size(); ++i) {
    const Eigen::AngleAxisd d(truth[i].linear().transpose() * a * estimate[i].linear());
    rot += d.angle() * d.angle();
  }
  e.rotation_rmse_deg = std::sqrt(rot / static_cast<double>(estimate.size())) * 180.0 / M_PI;
  return e;
}

std::vector<double> tiltErrorsDeg(const std::vector<Eigen::Isometry3d>& estimate,
                                  const std::vector<Eigen::Isometry3d>& truth, const Eigen::Matrix3d& rotation,
                                  const Eigen::Vector3d& up) {
  if (estimate.size() != truth.size())
    throw InputError("tilt error", "needs equally long trajectories (estimate " + std::to_string(estimate.size()) +
                                       ", truth " + std::to_string(truth.size()) + ")");
  const Eigen::Vector3d g = up.normalized();
  std::vector<double> out;
  out.reserve(estimate.size());
  for (size_t i = 0; i < estimate.size(); ++i) {
    const Eigen::Vector3d seen = truth[i].linear().transpose() * g;
    const Eigen::Vector3d estimated = (rotation * estimate[i].linear()).transpose() * g;
    out.push_back(std::atan2(seen.cross(estimated).norm(), seen.dot(estimated)) * 180 / M_PI);
  }
  return out;
}

DepthError depthError(const std::vector<cv::Mat>& estimate, const std::vector<cv::Mat>& confidence,
                      const std::vector<cv::Mat>& truth, double min_confidence) {
  if (estimate.size() != truth.size() || confidence.size() != truth.size())
    throw InputError("depth error", "needs as many estimates and confidences as truth frames");
  DepthError e;
  std::vector<float> est, gt;
  for (size_t f = 0; f < truth.size(); ++f) {
    const cv::Mat& t = truth[f];
    if (t.type() != CV_32F) throw InputError("depth error", "truth frame " + std::to_string(f) + " is not CV_32F");
    const bool has = !estimate[f].empty();
    if (has && (estimate[f].size() != t.size() || confidence[f].size() != t.size() ||
                estimate[f].type() != CV_32F || confidence[f].type() != CV_32F))
      throw InputError("depth error", "frame " + std::to_string(f) + ": estimate, confidence and truth differ in size or type");
    for (int r = 0; r < t.rows; ++r) {
      for (int c = 0; c < t.cols; ++c) {
        const float g = t.at<float>(r, c);
        if (!std::isfinite(g) || g <= 0) continue;
        ++e.truth_pixels;
        if (!has) continue;
        const float d = estimate[f].at<float>(r, c);
        if (!std::isfinite(d) || d <= 0 || confidence[f].at<float>(r, c) < min_confidence) continue;
        est.push_back(d);
        gt.push_back(g);
      }
    }
  }
  e.confident_pixels = static_cast<long>(est.size());
  e.confident_fraction = e.truth_pixels ? static_cast<double>(e.confident_pixels) / e.truth_pixels : 0.0;
  if (est.empty()) {
    e.abs_rel = e.scale = std::numeric_limits<double>::quiet_NaN();
    return e;
  }
  std::vector<double> ratio(est.size());
  for (size_t i = 0; i < est.size(); ++i) ratio[i] = gt[i] / est[i];
  std::nth_element(ratio.begin(), ratio.begin() + static_cast<long>(ratio.size() / 2), ratio.end());
  e.scale = ratio[ratio.size() / 2];
  double sum = 0;
  for (size_t i = 0; i < est.size(); ++i) sum += std::abs(e.scale * est[i] - gt[i]) / gt[i];
  e.abs_rel = sum / static_cast<double>(est.size());
  return e;
}

}  // namespace valerant
