#include "valerant/geometry/goal_move.h"

#include <cmath>
#include <vector>

#include "valerant/geometry/open_direction.h"

namespace valerant {

std::optional<GoalMove> goalMove(const CoverageGrid& grid, const std::set<Cell>& blocked,
                                 const FrontierDistance& goal, const Eigen::Vector2d& position,
                                 double heading_angle, double max_cells) {
  const Cell here{static_cast<int>(std::floor(position.x() + 0.5)), static_cast<int>(std::floor(position.y() + 0.5))};
  const std::vector<Cell> path = goal.path(here, max_cells);
  for (auto it = path.rbegin(); it != path.rend(); ++it) {
    const Eigen::Vector2d to = Eigen::Vector2d(it->first, it->second) - position;
    const double distance = to.norm();
    const double angle = std::atan2(to.y(), to.x());
    if (freeRayCells(grid, blocked, position, angle, distance) >= distance - 0.5)
      return GoalMove{turnDeg(heading_angle, angle), distance, *it};
  }
  return std::nullopt;
}

}  // namespace valerant
