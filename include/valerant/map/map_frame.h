#pragma once
// The asset frame of a run's map: the frame game-engine exports are written in.
// Metres, Y up, right-handed (glTF's convention), origin on the floor under the start
// camera (the spawn's feet), -Z along the start heading (the way the spawn looks), +X
// to its right.
//
// How the scale is known. A monocular SLAM map has an arbitrary scale, but its camera
// is a player's eye, a known height over the floor (world.eye_height_units /
// quake3::kUnitsPerMetre = 50 / 32 = 1.5625 m in Quake III). The anchor floor of the
// exploration grid (coverage_grid.h) measures that height in map units (kappa_0), so
//     metres per map unit = eye height in metres / kappa_0     ("eye height").
// A metric SLAM (the oracle: its map is the BSP frame in metres) gives the scale
// directly: 1 ("metric slam"). Up is the anchor floor's normal rather than the map's
// z axis, so the asset is level whatever way the SLAM map is tilted.
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <string>

#include "valerant/config/config.h"
#include "valerant/geometry/floor_plane.h"

namespace valerant {

struct MapFrame {
  Eigen::Vector3d foot = Eigen::Vector3d::Zero();     // anchor camera's foot point, map frame
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();      // anchor floor normal (unit)
  Eigen::Vector3d forward = Eigen::Vector3d::UnitX(); // start heading along the floor (unit, normal to up)
  double eye_height = 1;                              // kappa_0, map units
  double metres_per_unit = 1;
  std::string scale_source;                           // "metric slam" or "eye height"

  // Map frame to asset frame (a similarity: scale, rotation, translation).
  Eigen::Affine3d mapToAsset() const;
  // The anchor floor with its camera above the foot point (the grid's anchor).
  FloorPlane anchorFloor() const;
  // (u, v) on the anchor floor, u along forward, v = up x forward: the coordinates of
  // CoverageGrid::floorCoordinates and of FloorGrid.
  Eigen::Vector2d floorCoordinates(const Eigen::Vector3d& map_point) const;
  Eigen::Vector3d floorPoint(const Eigen::Vector2d& uv) const;
};

// The frame of the exploration grid's anchor: the start floor (with its camera) and the
// start heading, as CoverageGrid takes them. `metric_slam`: the map is in metres already.
MapFrame mapFrameOf(const FloorPlane& anchor, const Eigen::Vector3d& heading, bool metric_slam, const Config& config);

nlohmann::json toJson(const MapFrame& frame);
// Throws InputError naming `source` when a field is missing or malformed.
MapFrame mapFrameFromJson(const nlohmann::json& json, const std::string& source);

}  // namespace valerant
