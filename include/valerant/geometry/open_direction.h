#pragma once
// Where the agent could walk next, measured on the coverage grid ([ours],
// policy.open_turn and policy.opening_weight; docs/whole_level.md). Angles lie on the
// anchor floor in the grid's axes (u, v), counter-clockwise seen from above (v = n x u,
// so a left turn increases the angle).
//  - free ray R(c, phi, max): from the centre of cell c (or any point) along phi, the
//    distance in cells walked, sampled every half cell, before the first sample whose
//    cell is in `blocked` (F) or cannot be stepped into from the cell before it
//    (CoverageGrid::traversable: walkable, and with the surface layer no higher or lower
//    than max_cell_rise); at most `max`.
//  - opening O(c, phi) = R(c, phi, cells_per_d_fwd) / cells_per_d_fwd, in [0, 1]: the
//    share of a forward action that fits ahead of a heading.
//  - open direction: among `rays` angles evenly spaced from the current heading whose
//    turn is at least min_turn_deg, those with the longest R(c, phi, grid size); of the
//    widest run of neighbouring such angles (of equal ones, the first counter-clockwise
//    from the heading), the middle one (the more clockwise of two): the middle of an
//    opening rather than its edge.
#include <Eigen/Core>
#include <optional>
#include <set>

#include "valerant/geometry/coverage_grid.h"

namespace valerant {

// Angle of a map-frame direction projected onto the grid's floor, radians.
double floorAngle(const CoverageGrid& grid, const Eigen::Vector3d& direction);
// Angle of the line from cell `from` to cell `to`, radians.
double cellAngle(const Cell& from, const Cell& to);
// The turn from angle `from` to angle `to` (radians), degrees in (-180, 180], left positive.
double turnDeg(double from, double to);

double freeRayCells(const CoverageGrid& grid, const std::set<Cell>& blocked, const Cell& from, double angle,
                    double max_cells);
// The same from any point in cell coordinates (CoverageGrid::cellCoordinates), not a cell's centre.
double freeRayCells(const CoverageGrid& grid, const std::set<Cell>& blocked, const Eigen::Vector2d& from,
                    double angle, double max_cells);

double opening(const CoverageGrid& grid, const std::set<Cell>& blocked, const Cell& from, double angle);

struct OpenDirection {
  double turn_deg = 0;   // left positive, in (-180, 180]
  double ray_cells = 0;  // R along it
};
// Empty when no direction has a free ray of half a cell or more.
std::optional<OpenDirection> openDirection(const CoverageGrid& grid, const std::set<Cell>& blocked, const Cell& from,
                                           double heading_angle, int rays, double min_turn_deg);

}  // namespace valerant
