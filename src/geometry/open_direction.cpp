#include "valerant/geometry/open_direction.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace valerant {

double floorAngle(const CoverageGrid& grid, const Eigen::Vector3d& direction) {
  const Eigen::Vector2d d = grid.floorCoordinates(direction) - grid.floorCoordinates(Eigen::Vector3d::Zero());
  return std::atan2(d.y(), d.x());
}

double cellAngle(const Cell& from, const Cell& to) {
  return std::atan2(to.second - from.second, to.first - from.first);
}

double turnDeg(double from, double to) {
  double turn = std::remainder((to - from) * 180.0 / M_PI, 360.0);  // [-180, 180]
  if (turn <= -180.0) turn += 360.0;
  return turn;
}

double freeRayCells(const CoverageGrid& grid, const std::set<Cell>& blocked, const Cell& from, double angle,
                    double max_cells) {
  return freeRayCells(grid, blocked, Eigen::Vector2d(from.first, from.second), angle, max_cells);
}

double freeRayCells(const CoverageGrid& grid, const std::set<Cell>& blocked, const Eigen::Vector2d& from,
                    double angle, double max_cells) {
  const double step = 0.5;
  const double du = std::cos(angle), dv = std::sin(angle);
  double walked = 0;
  Cell previous{static_cast<int>(std::floor(from.x() + 0.5)), static_cast<int>(std::floor(from.y() + 0.5))};
  if (!grid.walkable(previous) || blocked.count(previous)) return 0;  // no ray out of a blocked cell
  for (double t = step; t <= max_cells + 1e-9; t += step) {
    const Cell c{static_cast<int>(std::floor(from.x() + t * du + 0.5)),
                 static_cast<int>(std::floor(from.y() + t * dv + 0.5))};
    if (c != previous && (!grid.traversable(previous, c) || blocked.count(c))) break;
    previous = c;
    walked = t;
  }
  return walked;
}

double opening(const CoverageGrid& grid, const std::set<Cell>& blocked, const Cell& from, double angle) {
  const double action = grid.cellsPerForwardAction();
  return freeRayCells(grid, blocked, from, angle, action) / action;
}

std::optional<OpenDirection> openDirection(const CoverageGrid& grid, const std::set<Cell>& blocked, const Cell& from,
                                           double heading_angle, int rays, double min_turn_deg) {
  // Ray k turns 360 k / rays degrees left; excluded rays get -1.
  std::vector<double> length(rays, -1.0);
  double longest = 0;
  for (int k = 0; k < rays; ++k) {
    const double turn_deg = 360.0 * k / rays;
    if (std::min(turn_deg, 360.0 - turn_deg) < min_turn_deg) continue;
    length[k] = freeRayCells(grid, blocked, from, heading_angle + turn_deg * M_PI / 180.0, grid.size());
    longest = std::max(longest, length[k]);
  }
  if (longest <= 0) return std::nullopt;
  auto isLongest = [&](int k) { return length[((k % rays) + rays) % rays] >= longest; };
  // Runs of neighbouring longest rays, walked from a ray that does not continue one
  // (ray 0 when all are longest).
  int first = 0;
  while (first < rays && isLongest(first) && isLongest(first - 1)) ++first;
  if (first == rays) first = 0;
  int best_start = -1, best_run = 0;
  for (int k = first; k < first + rays;) {
    if (!isLongest(k)) {
      ++k;
      continue;
    }
    int run = 0;
    while (run < rays && isLongest(k + run)) ++run;
    if (run > best_run) best_start = k, best_run = run;
    k += run;
  }
  double turn_deg = 360.0 * ((best_start + (best_run - 1) / 2) % rays) / rays;
  if (turn_deg > 180.0) turn_deg -= 360.0;
  return OpenDirection{turn_deg, longest};
}

}  // namespace valerant
