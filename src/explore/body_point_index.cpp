#include "valerant/explore/body_point_index.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace valerant {
namespace {

constexpr double kMinAxisCosine = 0.5;  // samples tilted further from n0 go by brute force
constexpr double kMaxCellsPerAxis = 1e9;  // keeps cell indices far inside long long

bool lessCell(long long ax, long long ay, long long bx, long long by) { return ax < bx || (ax == bx && ay < by); }

}  // namespace

BodyPointIndex::BodyPointIndex(const std::vector<Eigen::Vector3d>& points, const std::vector<FloorPlane>& samples,
                               double radius, double max_radius)
    : max_radius_(max_radius) {
  if (max_radius != 0 && !(max_radius >= radius))
    throw std::invalid_argument("BodyPointIndex: max_radius " + std::to_string(max_radius) +
                                " is below the radius " + std::to_string(radius));
  const FloorPlane* reference = nullptr;
  for (const FloorPlane& s : samples)
    if (s.cameraHeight() > 0 && std::isfinite(s.cameraHeight()) && s.n.allFinite() && s.c.allFinite()) {
      reference = &s;
      break;
    }
  binned_.reserve(points.size());
  for (size_t k = 0; k < points.size(); ++k) binned_.push_back({0, 0, points[k], k});
  if (!reference || points.empty() || !(radius > 0)) return;
  n0_ = reference->n.normalized();
  e1_ = n0_.unitOrthogonal();
  e2_ = n0_.cross(e1_);
  double extent = 0;
  u_min_ = u_max_ = points.front().dot(n0_);
  for (const auto& p : points) {
    const double u = p.dot(n0_);
    u_min_ = std::min(u_min_, u);
    u_max_ = std::max(u_max_, u);
    extent = std::max({extent, std::abs(p.dot(e1_)), std::abs(p.dot(e2_))});
  }
  cell_ = std::max(radius * reference->cameraHeight(), extent / kMaxCellsPerAxis);
  if (!(cell_ > 0) || !std::isfinite(cell_)) return;
  indexed_ = true;  // span() needs it
  if (max_radius_ > 0) keepReachable(samples);
  for (auto& b : binned_) {
    b.ix = static_cast<long long>(std::floor(b.position.dot(e1_) / cell_));
    b.iy = static_cast<long long>(std::floor(b.position.dot(e2_) / cell_));
  }
  std::sort(binned_.begin(), binned_.end(),
            [](const Binned& a, const Binned& b) { return lessCell(a.ix, a.iy, b.ix, b.iy); });
}

void BodyPointIndex::keepReachable(const std::vector<FloorPlane>& samples) {
  // The bounding box of every sample's span at max_radius; a sample without a floor
  // visits nothing, one counted by brute force could visit anything.
  double a_min = std::numeric_limits<double>::infinity(), a_max = -a_min, b_min = a_min, b_max = -a_min;
  for (const FloorPlane& s : samples) {
    if (!(s.cameraHeight() > 0)) continue;
    double a_lo, a_hi, b_lo, b_hi;
    if (!span(s, max_radius_, &a_lo, &a_hi, &b_lo, &b_hi)) return;
    a_min = std::min(a_min, a_lo);
    a_max = std::max(a_max, a_hi);
    b_min = std::min(b_min, b_lo);
    b_max = std::max(b_max, b_hi);
  }
  binned_.erase(std::remove_if(binned_.begin(), binned_.end(),
                               [&](const Binned& b) {
                                 const double a = b.position.dot(e1_), c = b.position.dot(e2_);
                                 return !(a >= a_min && a <= a_max && c >= b_min && c <= b_max);
                               }),
                binned_.end());
}

void BodyPointIndex::checkRadius(double radius) const {
  if (max_radius_ > 0 && radius > max_radius_)
    throw std::invalid_argument("BodyPointIndex: radius " + std::to_string(radius) + " is over the index's max_radius " +
                                std::to_string(max_radius_));
}

std::vector<BodyPointIndex::Binned>::const_iterator BodyPointIndex::firstAt(long long ix, long long iy) const {
  return std::lower_bound(binned_.begin(), binned_.end(), std::make_pair(ix, iy),
                          [](const Binned& b, const std::pair<long long, long long>& key) {
                            return lessCell(b.ix, b.iy, key.first, key.second);
                          });
}

bool BodyPointIndex::span(const FloorPlane& sample, double radius, double* a_lo, double* a_hi, double* b_lo,
                          double* b_hi) const {
  const double r = radius * sample.cameraHeight();
  const double cosine = sample.n.dot(n0_);
  if (!indexed_ || !(cosine >= kMinAxisCosine) || std::abs(sample.n.norm() - 1) > 1e-9 || !sample.c.allFinite())
    return false;
  // p = c + t n + e with |e| <= r counts; p.n0 in [u_min, u_max] bounds t, and the
  // projection of p across n0 then lies within r of the axis segment's projection.
  const double c_u = sample.c.dot(n0_);
  const double t_a = (u_min_ - c_u - r) / cosine, t_b = (u_max_ - c_u + r) / cosine;
  auto along = [&](const Eigen::Vector3d& axis, double* lo, double* hi) {
    const double c = sample.c.dot(axis), slope = sample.n.dot(axis);
    const double margin = 1e-9 * (1 + std::abs(c) + std::abs(t_a) + std::abs(t_b) + r);
    *lo = c + std::min(t_a * slope, t_b * slope) - r - margin;
    *hi = c + std::max(t_a * slope, t_b * slope) + r + margin;
  };
  along(e1_, a_lo, a_hi);
  along(e2_, b_lo, b_hi);
  return std::isfinite(*a_lo) && std::isfinite(*a_hi) && std::isfinite(*b_lo) && std::isfinite(*b_hi);
}

bool BodyPointIndex::searchBox(const FloorPlane& sample, double radius, long long box[4], double* radius2) const {
  const double r = radius * sample.cameraHeight();
  *radius2 = r * r;
  double a_lo, a_hi, b_lo, b_hi;
  if (binned_.empty() || !span(sample, radius, &a_lo, &a_hi, &b_lo, &b_hi)) return false;
  // Cells are clamped to the indexed points' range (a far sample must not loop over
  // billions of empty cells); a box wider than a 16th of the points is cheaper by brute force.
  auto cellOf = [&](double v) {
    return static_cast<long long>(std::floor(std::clamp(v / cell_, -kMaxCellsPerAxis - 1, kMaxCellsPerAxis + 1)));
  };
  box[0] = std::max(binned_.front().ix, cellOf(a_lo));
  box[1] = std::min(binned_.back().ix, cellOf(a_hi));
  box[2] = cellOf(b_lo);
  box[3] = cellOf(b_hi);
  return box[1] - box[0] + 1 <= static_cast<long long>(binned_.size() / 16) + 1;
}

int BodyPointIndex::count(const FloorPlane& sample, double radius) const {
  int n = 0;
  forEachWithin(sample, radius, [&n](size_t) { ++n; });
  return n;
}

}  // namespace valerant
