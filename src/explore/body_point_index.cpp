#include "valerant/explore/body_point_index.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace valerant {
namespace {

constexpr double kMaxCellsPerAxis = 1e9;  // keeps cell indices far inside long long

bool lessCell(long long ax, long long ay, long long bx, long long by) { return ax < bx || (ax == bx && ay < by); }

}  // namespace

BodyPointIndex::BodyPointIndex(const std::vector<Eigen::Vector3d>& points, const std::vector<FloorPlane>& samples,
                               double radius, double max_radius)
    : max_radius_(max_radius) {
  if (max_radius != 0 && !(max_radius >= radius))
    throw std::invalid_argument("BodyPointIndex: max_radius " + std::to_string(max_radius) +
                                " is below the radius " + std::to_string(radius));
  const FloorPlane* reference = referenceSample(samples);
  binned_.reserve(points.size());
  for (size_t k = 0; k < points.size(); ++k) binned_.push_back({0, 0, points[k], k});
  if (!reference || points.empty() || !(radius > 0)) return;
  const BodyReach reach(*reference);
  double extent = 0;
  u_min_ = u_max_ = reach.along(points.front());
  for (const auto& p : points) {
    const double u = reach.along(p);
    u_min_ = std::min(u_min_, u);
    u_max_ = std::max(u_max_, u);
    extent = std::max({extent, std::abs(reach.across1(p)), std::abs(reach.across2(p))});
  }
  cell_ = std::max(radius * reference->cameraHeight(), extent / kMaxCellsPerAxis);
  if (!(cell_ > 0) || !std::isfinite(cell_)) return;
  reach_ = reach;
  if (max_radius_ > 0) keepReachable(samples);
  for (auto& b : binned_) {
    b.ix = static_cast<long long>(std::floor(reach.across1(b.position) / cell_));
    b.iy = static_cast<long long>(std::floor(reach.across2(b.position) / cell_));
  }
  std::sort(binned_.begin(), binned_.end(),
            [](const Binned& a, const Binned& b) { return lessCell(a.ix, a.iy, b.ix, b.iy); });
}

void BodyPointIndex::keepReachable(const std::vector<FloorPlane>& samples) {
  const auto box = reach_->spanOfAll(samples, max_radius_, u_min_, u_max_);
  if (!box) return;  // some sample is counted by brute force: it may visit anything
  const ReachableBox reachable{*reach_, *box};
  binned_.erase(std::remove_if(binned_.begin(), binned_.end(),
                               [&](const Binned& b) { return !reachable.contains(b.position); }),
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

bool BodyPointIndex::searchBox(const FloorPlane& sample, double radius, long long box[4], double* radius2) const {
  const double r = radius * sample.cameraHeight();
  *radius2 = r * r;
  if (binned_.empty() || !reach_) return false;
  const auto span = reach_->span(sample, radius, u_min_, u_max_);
  if (!span) return false;
  // Cells are clamped to the indexed points' range (a far sample must not loop over
  // billions of empty cells); a box wider than a 16th of the points is cheaper by brute force.
  auto cellOf = [&](double v) {
    return static_cast<long long>(std::floor(std::clamp(v / cell_, -kMaxCellsPerAxis - 1, kMaxCellsPerAxis + 1)));
  };
  box[0] = std::max(binned_.front().ix, cellOf(span->a_lo));
  box[1] = std::min(binned_.back().ix, cellOf(span->a_hi));
  box[2] = cellOf(span->b_lo);
  box[3] = cellOf(span->b_hi);
  return box[1] - box[0] + 1 <= static_cast<long long>(binned_.size() / 16) + 1;
}

int BodyPointIndex::count(const FloorPlane& sample, double radius) const {
  int n = 0;
  forEachWithin(sample, radius, [&n](size_t) { ++n; });
  return n;
}

}  // namespace valerant
