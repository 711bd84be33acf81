#pragma once
// The exploration grid of the policy (paper eq. 2, appendix A): grid_cells x grid_cells
// (the paper's 128; ours 512, to hold whole levels: config/valerant.yaml) cells whose
// width is one eighth of a nominal forward action, anchored at the start pose on the
// floor plane. Everything is floor-normalised: a cell is (d_fwd / 8) * kappa_0 map units
// wide, kappa_0 the camera-to-floor distance at the anchor, d_fwd the forward action
// divided by the eye height (256 / 50), so the grid means the same under any SLAM scale.
//
// Terms, for a candidate whose trajectory samples have floor positions x_1..x_L:
//  - visited cells: cells containing a committed trajectory sample.
//  - C_new   = |cells(x_1..x_L) \ visited| / cells_per_d_fwd
//              (a straight forward action into unvisited space scores about 1).
//  - frontier: observed-floor cells (points with |h| <= floor_band) with at least one
//              4-neighbour never observed as floor.
//  - C_front = 1 / (1 + D / cells_per_d_fwd), D the distance in cells from the last
//              sample's cell to the nearest frontier cell (0 when there is no frontier).
//  - C       = C_new + frontier_weight * C_front
//  - P       = |horizontal displacement x_L - x_0| / (d_fwd * kappa_0): forward progress
//              in nominal forward actions, independent of the direction turned.
// Positions outside the grid are clamped out (they add no cells).
//
// A third layer counts obstacle points ([ours], policy.obstacle_min_points): map points
// between the collision test's heights (height_low <= h <= height_high). It feeds the
// whole-level goal (frontier_distance.h) and the open direction (open_direction.h);
// the paper's terms above do not read it:
//  - obstacle: a cell holding at least obstacle_min_points obstacle points.
//  - walkable: a visited cell (the agent stood there), or observed floor that is no obstacle.
//  - unknown:  neither observed floor, obstacle nor visited.
// With policy.max_cell_rise > 0 a fourth layer, the surfaces (surface_layer.h), replaces
// the last two for the whole-level terms, storeys and stairs included:
//  - walkable: a cell with a surface height (visited cells: the floor stood on);
//  - unknown:  no point seen in it and not visited;
//  - a step into a neighbour (traversable): both walkable, rising at most max_cell_rise
//    (any drop).
// Without it a step is any walkable neighbour: the flat model.
#include <Eigen/Geometry>
#include <cstdint>
#include <set>
#include <utility>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/geometry/floor_plane.h"
#include "valerant/geometry/surface_layer.h"

namespace valerant {

using Cell = std::pair<int, int>;

struct CoverageTerms {
  double c_new = 0;
  double c_front = 0;
  double coverage = 0;  // C
  double progress = 0;  // P
  std::set<Cell> cells;  // cells the candidate passes through
};

class CoverageGrid {
 public:
  // `anchor`: floor (with camera centre) at the start pose; `heading`: the start
  // camera's optical axis in the map frame. `d_fwd_normalised` = d_fwd / eye height.
  CoverageGrid(const PolicyConfig& config, const FloorPlane& anchor, const Eigen::Vector3d& heading,
               double d_fwd_normalised);

  // Cell of a map-frame point projected onto the anchor floor; false when outside.
  bool cellOf(const Eigen::Vector3d& p, Cell& cell) const;
  double cellSize() const { return cell_size_; }
  int cellsPerForwardAction() const { return config_.cells_per_d_fwd; }
  int size() const { return size_; }

  void markVisited(const Eigen::Vector3d& camera_centre);
  void markObservedFloor(const Eigen::Vector3d& point);
  void markObstaclePoint(const Eigen::Vector3d& point);
  // A map point for the surface layer (one below the obstacle band's top over its own
  // keyframe's floor); ignored without the layer.
  void markSurfacePoint(const Eigen::Vector3d& point);
  // With carving (surface_layer.h), the ray from a keyframe's eye to one of its surface
  // points: the cells it crosses before the point's own, at the heights it crosses them,
  // while it runs above `lowest_own_height` over its keyframe's floor (from 1 at the eye to
  // `point_own_height` at the point), so that rays ending on the floor do not carve it.
  void markSurfaceRay(const Eigen::Vector3d& eye, const Eigen::Vector3d& point, double point_own_height,
                      double lowest_own_height);
  bool surfaces() const { return config_.max_cell_rise > 0; }
  // Normalised height of a map-frame point over the anchor floor.
  double heightOf(const Eigen::Vector3d& p) const { return normal_.dot(p - origin_) / kappa_; }
  bool visited(const Cell& c) const { return inside(c) && visited_[index(c)]; }
  bool observed(const Cell& c) const { return inside(c) && observed_[index(c)]; }
  size_t observedCells() const { return observed_cells_; }  // cells marked as observed floor
  bool obstacle(const Cell& c) const {
    return inside(c) && obstacle_points_[index(c)] >= static_cast<uint32_t>(config_.obstacle_min_points);
  }
  bool walkable(const Cell& c) const;
  bool unknown(const Cell& c) const;
  // Whether the agent can walk from `from` into its neighbour `to` (see above).
  bool traversable(const Cell& from, const Cell& to) const;
  // A surface seen in the cell, not only stood on: the layer's `seen` (with surfaces),
  // else observed floor.
  bool seenWalkable(const Cell& c) const;
  bool inside(const Cell& c) const { return c.first >= 0 && c.second >= 0 && c.first < size_ && c.second < size_; }
  bool isFrontier(const Cell& c) const;

  // Scores a candidate from its camera centres (first = the start of the candidate).
  CoverageTerms score(const std::vector<Eigen::Vector3d>& camera_centres) const;

  // (u, v) of a map-frame point on the anchor floor, in map units from the anchor.
  Eigen::Vector2d floorCoordinates(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d d = p - origin_;
    return {d.dot(axis_u_), d.dot(axis_v_)};
  }
  // Where a map-frame point lies on the grid, in cells: cell (i, j) spans
  // [i - 1/2, i + 1/2) x [j - 1/2, j + 1/2), so cellOf rounds these coordinates.
  Eigen::Vector2d cellCoordinates(const Eigen::Vector3d& p) const {
    return floorCoordinates(p) / cell_size_ + Eigen::Vector2d::Constant(size_ / 2);
  }
  // Map-frame position of a cell centre on the anchor floor (for drawing).
  Eigen::Vector3d cellCentre(const Cell& c) const;

 private:
  size_t index(const Cell& c) const { return static_cast<size_t>(c.first) * size_ + c.second; }
  double frontierDistance(const Cell& from) const;

  PolicyConfig config_;
  int size_;
  double cell_size_, d_fwd_map_, kappa_;
  Eigen::Vector3d origin_, axis_u_, axis_v_, normal_;
  std::vector<uint8_t> visited_, observed_;
  size_t observed_cells_ = 0;
  std::vector<uint32_t> obstacle_points_;
  SurfaceLayer surface_;
};

}  // namespace valerant
