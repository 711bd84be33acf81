#pragma once
// Where a player can walk, as polygons a game engine's navigation can take: the free
// floor cells of the floor grid (map_fusion.h), with unobserved gaps of a cell or so
// closed (far floor is sampled sparser than the grid: a morphological closing), that
// keep a body's clearance from every body-level obstacle cell, traced into polygons
// with holes by OpenCV (findContours).
// Polygons lie on the asset frame's floor, as (x, z) in metres (map_frame.h). A boundary
// runs through the centres of the outermost walkable cells (OpenCV traces pixel
// centres), so a polygon lies up to half a cell inside its cells: the safe side for an
// agent. Storeys are not told apart (the grid is 2D).
//
// walkable.json:
//   {"frame": "...", "cell_size_m": s, "clearance_m": c, "area_m2": a,
//    "polygons": [{"outer": [[x, z], ...], "holes": [[[x, z], ...], ...]}, ...]}
#include <Eigen/Core>
#include <string>
#include <vector>

#include "valerant/map/map_frame.h"
#include "valerant/map/map_fusion.h"

namespace valerant {

struct WalkablePolygon {
  std::vector<Eigen::Vector2d> outer;               // (x, z), metres
  std::vector<std::vector<Eigen::Vector2d>> holes;  // (x, z), metres
};

struct WalkableArea {
  double cell_size_m = 0;
  double clearance_m = 0;
  std::vector<WalkablePolygon> polygons;

  double areaSquareMetres() const;                 // outer rings minus holes
  bool contains(const Eigen::Vector2d& xz) const;  // a boundary point counts as inside
};

struct WalkableParams {
  double clearance = 0;    // map units from a walkable cell's centre to the nearest obstacle cell's near edge
  int close_cells = 0;     // unobserved gaps up to this many cells wide become floor
  double min_area_m2 = 0;  // smaller islands are dropped
};

WalkableArea walkableArea(const FloorGrid& grid, const MapFrame& frame, const WalkableParams& params);

void writeWalkableJson(const std::string& path, const WalkableArea& area, bool overwrite);
// Throws InputError naming the file when it is missing, truncated or malformed.
WalkableArea readWalkableJson(const std::string& path);

}  // namespace valerant
