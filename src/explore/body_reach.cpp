#include "valerant/explore/body_reach.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace valerant {
namespace {

constexpr double kMinAxisCosine = 0.5;  // samples tilted further from n0 have no span

}  // namespace

const FloorPlane* referenceSample(const std::vector<FloorPlane>& samples) {
  for (const FloorPlane& s : samples)
    if (s.cameraHeight() > 0 && std::isfinite(s.cameraHeight()) && s.n.allFinite() && s.c.allFinite()) return &s;
  return nullptr;
}

PlaneBox PlaneBox::joined(const PlaneBox& other) const {
  return {std::min(a_lo, other.a_lo), std::max(a_hi, other.a_hi), std::min(b_lo, other.b_lo),
          std::max(b_hi, other.b_hi)};
}

BodyReach::BodyReach(const FloorPlane& reference) {
  n0_ = reference.n.normalized();
  e1_ = n0_.unitOrthogonal();
  e2_ = n0_.cross(e1_);
}

std::optional<PlaneBox> BodyReach::span(const FloorPlane& sample, double radius, double u_min, double u_max) const {
  const double r = radius * sample.cameraHeight();
  const double cosine = sample.n.dot(n0_);
  if (!(cosine >= kMinAxisCosine) || std::abs(sample.n.norm() - 1) > 1e-9 || !sample.c.allFinite()) return std::nullopt;
  const double c_u = sample.c.dot(n0_);
  const double t_a = (u_min - c_u - r) / cosine, t_b = (u_max - c_u + r) / cosine;
  PlaneBox box;
  auto along = [&](const Eigen::Vector3d& axis, double* lo, double* hi) {
    const double c = sample.c.dot(axis), slope = sample.n.dot(axis);
    const double margin = 1e-9 * (1 + std::abs(c) + std::abs(t_a) + std::abs(t_b) + r);
    *lo = c + std::min(t_a * slope, t_b * slope) - r - margin;
    *hi = c + std::max(t_a * slope, t_b * slope) + r + margin;
  };
  along(e1_, &box.a_lo, &box.a_hi);
  along(e2_, &box.b_lo, &box.b_hi);
  if (!(std::isfinite(box.a_lo) && std::isfinite(box.a_hi) && std::isfinite(box.b_lo) && std::isfinite(box.b_hi)))
    return std::nullopt;
  return box;
}

std::optional<PlaneBox> BodyReach::spanOfAll(const std::vector<FloorPlane>& samples, double radius, double u_min,
                                             double u_max) const {
  std::optional<PlaneBox> all;
  for (const FloorPlane& s : samples) {
    if (!(s.cameraHeight() > 0)) continue;  // counts nothing
    const auto box = span(s, radius, u_min, u_max);
    if (!box) return std::nullopt;
    all = all ? all->joined(*box) : *box;
  }
  return all;
}

}  // namespace valerant
