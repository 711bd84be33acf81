#pragma once
// The whole-level goal ([ours], policy.goal_weight; docs/whole_level.md). The paper's
// coverage terms only see one rollout; a long episode also needs a direction: the
// nearest unexplored space the agent can walk to. On the coverage grid's layers
// (coverage_grid.h: walkable, obstacle, unknown):
//  - goal frontier: an observed floor cell, no obstacle (with the surface layer: a seen
//    walkable surface), outside `blocked` and `no_goals`, with an unknown 4-neighbour. A
//    floor cell beside a wall has the wall's obstacle cell as neighbour, not an unknown
//    one: no frontier. (A visited cell never seen as floor is walkable but no frontier:
//    the unseen space behind the spawn is no goal until it has been looked at.)
//  - D(c): path distance in cells from c to the nearest goal frontier over walkable
//    cells outside `blocked` (the failed-region memory F; with dead_pocket.cross_failed
//    F is in `no_goals` instead: paths cross it, none ends there), 8-connected (steps 1 and
//    sqrt 2) where the grid lets the agent step (CoverageGrid::traversable: any walkable
//    neighbour, or with the surface layer one rising at most max_cell_rise, or lower): a
//    multi-source Dijkstra from every goal frontier over the steps reversed. Infinite
//    where no frontier is reachable.
//  - G = (D(start) - D'(end)) / cells_per_d_fwd, the approach to the goal in forward
//    actions, where D'(end) = D(end), or 0 when the end cell is unknown (the candidate
//    walks into unexplored space, the goal itself). G = 0 when D(start) or D'(end) is
//    infinite (no goal reachable; an end in an obstacle, in F or cut off) or either
//    cell is outside the grid: nothing to approach, so the paper's terms decide.
//  - path: from `start` (left out), the cells down the steepest descent of D (the
//    shortest path; of equal neighbours the first in row-major order) for at most
//    `max_cells` of path length, ending early at the frontier (D = 0).
//  - waypoint: the path's last cell, or, when the path reaches the frontier, the
//    frontier's unknown neighbour: where the goal lies as seen from the agent (the open
//    turn heads there).
#include <limits>
#include <optional>
#include <set>
#include <vector>

#include "valerant/geometry/coverage_grid.h"

namespace valerant {

class FrontierDistance {
 public:
  // `grid` must outlive it.
  FrontierDistance(const CoverageGrid& grid, std::set<Cell> blocked, std::set<Cell> no_goals = {});

  static constexpr double kUnreachable = std::numeric_limits<double>::infinity();
  bool isGoalFrontier(const Cell& c) const;
  int goalFrontierCells() const { return goal_frontier_cells_; }
  // D(c) in cells; kUnreachable outside the grid or where no frontier is reachable.
  double at(const Cell& c) const;
  // G of a candidate from `start` to `end` (cells), in forward actions.
  double goalTerm(const Cell& start, const Cell& end) const;
  // Empty when no frontier is reachable from `start` or `start` is a frontier.
  std::vector<Cell> path(const Cell& start, double max_cells) const;
  // Empty when no frontier is reachable from `start` or the path does not leave it.
  std::optional<Cell> waypoint(const Cell& start, double max_cells) const;

 private:
  // A step from `from` into its neighbour `to` (CoverageGrid::traversable), neither in F.
  bool passable(const Cell& from, const Cell& to) const;

  const CoverageGrid& grid_;
  std::set<Cell> blocked_;
  std::set<Cell> no_goals_;
  std::vector<double> distance_;  // row-major, grid.size()^2
  int goal_frontier_cells_ = 0;
};

}  // namespace valerant
