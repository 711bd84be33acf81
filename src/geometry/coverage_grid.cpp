#include "valerant/geometry/coverage_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace valerant {

CoverageGrid::CoverageGrid(const PolicyConfig& config, const FloorPlane& anchor, const Eigen::Vector3d& heading,
                           double d_fwd_normalised)
    : config_(config),
      size_(config.grid_cells),
      surface_(config.max_cell_rise, config.obstacle_min_points, config.surface_carving_ratio) {
  normal_ = anchor.n.normalized();
  kappa_ = anchor.cameraHeight();
  d_fwd_map_ = d_fwd_normalised * kappa_;
  cell_size_ = d_fwd_map_ / config.cells_per_d_fwd;
  origin_ = anchor.c - kappa_ * normal_;  // the anchor camera's foot point
  axis_u_ = heading - heading.dot(normal_) * normal_;
  if (axis_u_.norm() < 1e-9) axis_u_ = normal_.unitOrthogonal();  // looking straight down
  axis_u_.normalize();
  axis_v_ = normal_.cross(axis_u_);
  visited_.assign(static_cast<size_t>(size_) * size_, 0);
  observed_.assign(static_cast<size_t>(size_) * size_, 0);
  obstacle_points_.assign(static_cast<size_t>(size_) * size_, 0);
}

bool CoverageGrid::cellOf(const Eigen::Vector3d& p, Cell& cell) const {
  // The anchor sits at the centre of cell (size/2, size/2).
  const Eigen::Vector2d at = cellCoordinates(p);
  cell = {static_cast<int>(std::floor(at.x() + 0.5)), static_cast<int>(std::floor(at.y() + 0.5))};
  return inside(cell);
}

Eigen::Vector3d CoverageGrid::cellCentre(const Cell& c) const {
  return origin_ + (c.first - size_ / 2) * cell_size_ * axis_u_ + (c.second - size_ / 2) * cell_size_ * axis_v_;
}

void CoverageGrid::markVisited(const Eigen::Vector3d& camera_centre) {
  Cell c;
  if (!cellOf(camera_centre, c)) return;
  visited_[index(c)] = 1;
  if (surfaces()) surface_.addStand(index(c), heightOf(camera_centre) - 1.0);  // the eye is one eye height up
}

void CoverageGrid::markSurfacePoint(const Eigen::Vector3d& point) {
  Cell c;
  if (surfaces() && cellOf(point, c)) surface_.addPoint(index(c), heightOf(point));
}

void CoverageGrid::markSurfaceRay(const Eigen::Vector3d& eye, const Eigen::Vector3d& point, double point_own_height,
                                  double lowest_own_height) {
  if (!surfaces() || !surface_.carving()) return;
  // The ray runs from t = 0 (eye, own height 1) to t = 1 (point); it stops where its own
  // height falls to lowest_own_height, at the point's cell, or where it leaves the grid.
  const double t_stop =
      point_own_height < lowest_own_height ? (1.0 - lowest_own_height) / (1.0 - point_own_height) : 1.0;
  // Shifted by half a cell, cell (i, j) spans [i, i + 1) x [j, j + 1): a 2D DDA over it.
  const Eigen::Vector2d a = cellCoordinates(eye) + Eigen::Vector2d::Constant(0.5);
  const Eigen::Vector2d d = cellCoordinates(point) + Eigen::Vector2d::Constant(0.5) - a;
  const double from = heightOf(eye), rise = heightOf(point) - from;
  const Cell end{static_cast<int>(std::floor(a.x() + d.x())), static_cast<int>(std::floor(a.y() + d.y()))};
  Cell c{static_cast<int>(std::floor(a.x())), static_cast<int>(std::floor(a.y()))};
  constexpr double kNever = std::numeric_limits<double>::infinity();
  const int step_i = d.x() > 0 ? 1 : -1, step_j = d.y() > 0 ? 1 : -1;
  const double delta_i = d.x() != 0 ? 1.0 / std::abs(d.x()) : kNever;
  const double delta_j = d.y() != 0 ? 1.0 / std::abs(d.y()) : kNever;
  double next_i = d.x() != 0 ? ((step_i > 0 ? c.first + 1 : c.first) - a.x()) / d.x() : kNever;
  double next_j = d.y() != 0 ? ((step_j > 0 ? c.second + 1 : c.second) - a.y()) / d.y() : kNever;
  for (double t = 0; c != end && t < t_stop && inside(c);) {
    const double out = std::min({next_i, next_j, t_stop});
    surface_.addPass(index(c), from + t * rise, from + out * rise);
    if (next_i < next_j) {
      c.first += step_i;
      t = next_i;
      next_i += delta_i;
    } else {
      c.second += step_j;
      t = next_j;
      next_j += delta_j;
    }
  }
}

bool CoverageGrid::walkable(const Cell& c) const {
  if (visited(c)) return true;
  if (surfaces()) return inside(c) && surface_.height(index(c)).has_value();
  return observed(c) && !obstacle(c);
}

bool CoverageGrid::unknown(const Cell& c) const {
  if (!inside(c) || visited(c)) return false;
  if (surfaces()) return !surface_.seen(index(c));
  return !observed(c) && !obstacle(c);
}

bool CoverageGrid::traversable(const Cell& from, const Cell& to) const {
  if (!walkable(to)) return false;
  return !surfaces() || (inside(from) && surface_.step(index(from), index(to)));
}

bool CoverageGrid::seenWalkable(const Cell& c) const {
  if (surfaces()) return inside(c) && surface_.seen(index(c)) && walkable(c);
  return observed(c) && walkable(c);
}

void CoverageGrid::markObservedFloor(const Eigen::Vector3d& point) {
  Cell c;
  if (!cellOf(point, c) || observed_[index(c)]) return;
  observed_[index(c)] = 1;
  ++observed_cells_;
}

void CoverageGrid::markObstaclePoint(const Eigen::Vector3d& point) {
  Cell c;
  if (cellOf(point, c)) ++obstacle_points_[index(c)];
}

bool CoverageGrid::isFrontier(const Cell& c) const {
  if (!observed(c)) return false;
  const Cell neighbours[] = {{c.first + 1, c.second}, {c.first - 1, c.second},
                             {c.first, c.second + 1}, {c.first, c.second - 1}};
  for (const Cell& n : neighbours)
    if (inside(n) && !observed_[index(n)]) return true;
  return false;
}

double CoverageGrid::frontierDistance(const Cell& from) const {
  // A linear scan: 16k cells, five candidates a step; far below the SLAM's cost.
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < size_; ++i)
    for (int j = 0; j < size_; ++j)
      if (isFrontier({i, j})) best = std::min(best, std::hypot(i - from.first, j - from.second));
  return best;
}

CoverageTerms CoverageGrid::score(const std::vector<Eigen::Vector3d>& camera_centres) const {
  CoverageTerms t;
  if (camera_centres.empty()) return t;
  for (const auto& c : camera_centres) {
    Cell cell;
    if (cellOf(c, cell)) t.cells.insert(cell);
  }
  int fresh = 0;
  for (const Cell& c : t.cells) fresh += !visited_[index(c)];
  t.c_new = static_cast<double>(fresh) / config_.cells_per_d_fwd;
  Cell end;
  if (cellOf(camera_centres.back(), end)) {
    const double d = frontierDistance(end);
    t.c_front = std::isfinite(d) ? 1.0 / (1.0 + d / config_.cells_per_d_fwd) : 0.0;
  }
  t.coverage = t.c_new + config_.frontier_weight * t.c_front;
  Eigen::Vector3d move = camera_centres.back() - camera_centres.front();
  move -= move.dot(normal_) * normal_;
  t.progress = move.norm() / d_fwd_map_;
  return t;
}

}  // namespace valerant
