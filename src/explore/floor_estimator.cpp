#include "valerant/explore/floor_estimator.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <random>

namespace valerant {

FloorEstimator::FloorEstimator(const FloorConfig& config, const Eigen::Vector3d& initial_up,
                               double min_confidence, uint32_t seed)
    : config_(config), min_confidence_(min_confidence), up_(initial_up.normalized()), seed_(seed) {}

FloorEstimator::Fit FloorEstimator::fitLowerEnvelope(const std::vector<CloudPoint>& points,
                                                     const Eigen::Vector3d& c) {
  // Candidates: confident points below the camera, in the lowest share along `up`.
  std::vector<Eigen::Vector3d> below;
  std::vector<double> heights;
  for (const auto& p : points) {
    if (p.confidence < min_confidence_) continue;
    const Eigen::Vector3d x = p.position.cast<double>();
    const double s = up_.dot(x - c);
    if (s >= 0) continue;
    below.push_back(x);
    heights.push_back(s);
  }
  Fit best;
  if (below.size() < 3) return best;
  std::vector<double> sorted = heights;
  const size_t cut = std::max<size_t>(3, static_cast<size_t>(config_.lower_envelope_fraction * sorted.size()));
  std::nth_element(sorted.begin(), sorted.begin() + (cut - 1), sorted.end());
  const double threshold = sorted[cut - 1];
  std::vector<Eigen::Vector3d> candidates;
  for (size_t i = 0; i < below.size(); ++i)
    if (heights[i] <= threshold) candidates.push_back(below[i]);

  // Inlier band scales with the camera height so it means the same under any scale.
  std::vector<double> depths_below;
  for (const auto& x : candidates) depths_below.push_back(-up_.dot(x - c));
  std::nth_element(depths_below.begin(), depths_below.begin() + depths_below.size() / 2, depths_below.end());
  const double scale = has_relation_ ? relation_distance_ : depths_below[depths_below.size() / 2];
  const double band = config_.ransac_inlier_ratio * scale;

  std::mt19937 rng(seed_ * 1000003u + static_cast<uint32_t>(updates_));
  std::uniform_int_distribution<size_t> pick(0, candidates.size() - 1);
  auto countInliers = [&](const Eigen::Vector3d& q, const Eigen::Vector3d& n) {
    int count = 0;
    for (const auto& x : candidates) count += std::abs(n.dot(x - q)) <= band;
    return count;
  };
  for (int it = 0; it < config_.ransac_iterations; ++it) {
    const Eigen::Vector3d& a = candidates[pick(rng)];
    const Eigen::Vector3d& b = candidates[pick(rng)];
    const Eigen::Vector3d& d = candidates[pick(rng)];
    Eigen::Vector3d n = (b - a).cross(d - a);
    if (n.norm() < 1e-12) continue;
    n.normalize();
    const int support = countInliers(a, n);
    if (support > best.support) best = {a, n, support};
  }
  if (best.support < 3) return Fit{};
  // Least-squares refinement on the inliers: centroid and smallest principal axis.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> inliers;
  for (const auto& x : candidates)
    if (std::abs(best.n.dot(x - best.q)) <= band) inliers.push_back(x);
  for (const auto& x : inliers) centroid += x;
  centroid /= static_cast<double>(inliers.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& x : inliers) cov += (x - centroid) * (x - centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  Fit refined{centroid, eig.eigenvectors().col(0).normalized(), 0};
  refined.support = countInliers(refined.q, refined.n);
  return refined.support >= best.support ? refined : best;
}

FloorPlane FloorEstimator::at(const Eigen::Isometry3d& camera_to_map) const {
  FloorPlane plane;
  plane.c = camera_to_map.translation();
  if (!config_.enabled && has_global_) {
    plane.q = global_.q;
    plane.n = global_.n;
    return plane;
  }
  plane.n = (camera_to_map.linear() * relation_normal_camera_).normalized();
  plane.q = plane.c - relation_distance_ * plane.n;
  plane.known = has_relation_;
  return plane;
}

bool FloorEstimator::continuesFloor(double distance) {
  const double r = config_.max_distance_change;
  auto near = [r](double a, double b) { return a <= r * b && b <= r * a; };
  if (!has_relation_ || near(distance, relation_distance_)) {
    jump_keyframes_ = 0;
    return true;
  }
  // A jump: count the keyframes in a row that agree on the new distance.
  jump_keyframes_ = jump_keyframes_ > 0 && near(distance, jump_distance_) ? jump_keyframes_ + 1 : 1;
  jump_distance_ = distance;
  if (jump_keyframes_ < config_.relock_keyframes) return false;
  jump_keyframes_ = 0;
  return true;
}

FloorPlane FloorEstimator::update(const std::vector<CloudPoint>& points, const Eigen::Isometry3d& camera_to_map) {
  ++updates_;
  const Eigen::Vector3d c = camera_to_map.translation();
  // RF off: after the one calibration nothing is fitted any more.
  if (!config_.enabled && has_global_) return at(camera_to_map);

  Fit fit = fitLowerEnvelope(points, c);
  if (fit.support > 0 && fit.n.dot(c - fit.q) < 0) fit.n = -fit.n;  // toward the camera
  const double distance = fit.n.dot(c - fit.q);
  const bool accepted = fit.support >= config_.min_support &&
                        std::abs(fit.n.dot(up_)) >= config_.min_vertical_alignment && distance > 0;
  if (!accepted || !continuesFloor(distance)) {
    FloorPlane propagated = at(camera_to_map);
    propagated.support = fit.support;
    return propagated;
  }
  FloorPlane plane;
  plane.q = fit.q;
  plane.n = fit.n;
  plane.c = c;
  plane.reliable = true;
  plane.support = fit.support;
  relation_normal_camera_ = camera_to_map.linear().transpose() * fit.n;
  relation_distance_ = plane.cameraHeight();
  has_relation_ = true;
  up_ = fit.n;
  if (!config_.enabled) {
    global_ = plane;
    has_global_ = true;
  }
  return plane;
}

}  // namespace valerant
