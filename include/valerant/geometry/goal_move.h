#pragma once
// [ours] The goal move (policy.goal_move; docs/whole_level.md): a candidate that follows
// the shortest path to the nearest reachable frontier (frontier_distance.h). The
// paper's candidates are fixed arcs: in a room whose near side is mapped they rarely
// line up with the doorway the path leads through, so a goal term alone cannot lead
// the agent out. On the coverage grid, in cells, from the agent's position p
// (CoverageGrid::cellCoordinates) and the path c_1..c_n (FrontierDistance::path, at most
// `max_cells` of path, e.g. one forward action):
//  - target: the farthest c_k reached in a straight free line from p: the free ray from
//    p toward c_k (open_direction.h: walkable cells outside `blocked`, sampled every half
//    cell) is at least |c_k - p| - 1/2 long, i.e. it ends inside c_k;
//  - the move: turn in place to face c_k (turn_deg, left positive, from the heading
//    angle), then walk |c_k - p| cells straight ahead.
// Empty when no frontier is reachable, p's cell is a frontier, or no path cell is in a
// free line from p.
#include <Eigen/Core>
#include <optional>
#include <set>

#include "valerant/geometry/coverage_grid.h"
#include "valerant/geometry/frontier_distance.h"

namespace valerant {

struct GoalMove {
  double turn_deg = 0;    // left positive, in (-180, 180]
  double walk_cells = 0;  // straight ahead after the turn
  Cell target;            // the path cell it walks to
};

std::optional<GoalMove> goalMove(const CoverageGrid& grid, const std::set<Cell>& blocked,
                                 const FrontierDistance& goal, const Eigen::Vector2d& position,
                                 double heading_angle, double max_cells);

}  // namespace valerant
