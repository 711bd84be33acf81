#include "valerant/eval/walkable_truth.h"

#include <cmath>
#include <map>

#include "valerant/world/quake3/units.h"

namespace valerant {
namespace {

using Cell2 = std::pair<int, int>;

double ratio(int part, int whole) { return whole > 0 ? static_cast<double>(part) / whole : 0.0; }

}  // namespace

WalkableTruth evaluateWalkableTruth(const WalkableArea& walkable, const FloorGrid& grid, const MapFrame& frame,
                                    const Sim3& map_to_world_metres, const quake3::ReachableFloor& reachable,
                                    const Eigen::Vector3f& spawn_origin) {
  WalkableTruth t;
  const double cell = reachable.cell_size;
  // Reachable cells are centred on the spawn origin plus whole cells (the flood fill's
  // lattice); storeys merge into one 2D cell, keeping one floor height for its centre.
  auto reachableCell = [&](const Eigen::Vector3d& world_units) {
    return Cell2{static_cast<int>(std::lround((world_units.x() - spawn_origin.x()) / cell)),
                 static_cast<int>(std::lround((world_units.y() - spawn_origin.y()) / cell))};
  };
  std::map<Cell2, float> reachable_2d;
  for (const auto& c : reachable.cells) reachable_2d.emplace(reachableCell(c.cast<double>()), c.z());
  t.reachable_cells = static_cast<int>(reachable_2d.size());

  const Eigen::Affine3d to_asset = frame.mapToAsset();
  auto assetFloor = [&](const Eigen::Vector2d& uv) {
    const Eigen::Vector3d p = to_asset * frame.floorPoint(uv);
    return Eigen::Vector2d(p.x(), p.z());
  };
  auto cellCentre = [&](int row, int col) {
    return Eigen::Vector2d(grid.origin + grid.resolution * Eigen::Vector2d(col + 0.5, row + 0.5));
  };

  for (int row = 0; row < grid.height; ++row) {
    for (int col = 0; col < grid.width; ++col) {
      const Eigen::Vector2d uv = cellCentre(row, col);
      if (!walkable.contains(assetFloor(uv))) continue;
      ++t.walkable_cells;
      const Eigen::Vector3d world = map_to_world_metres.apply(frame.floorPoint(uv)) * quake3::kUnitsPerMetre;
      t.walkable_cells_reachable += reachable_2d.count(reachableCell(world)) > 0;
    }
  }

  const Eigen::Matrix3d world_to_map = map_to_world_metres.rotation.transpose() / map_to_world_metres.scale;
  for (const auto& [key, z] : reachable_2d) {
    const Eigen::Vector3d world_metres =
        Eigen::Vector3d(spawn_origin.x() + key.first * cell, spawn_origin.y() + key.second * cell, z) /
        quake3::kUnitsPerMetre;
    const Eigen::Vector2d uv =
        frame.floorCoordinates(world_to_map * (world_metres - map_to_world_metres.translation));
    const bool inside = walkable.contains(assetFloor(uv));
    t.reachable_cells_walkable += inside;
    const int col = static_cast<int>(std::floor((uv.x() - grid.origin.x()) / grid.resolution));
    const int row = static_cast<int>(std::floor((uv.y() - grid.origin.y()) / grid.resolution));
    if (col < 0 || row < 0 || col >= grid.width || row >= grid.height) continue;
    if (grid.cells[static_cast<size_t>(row) * grid.width + col] < 0) continue;  // never observed
    ++t.reachable_cells_explored;
    t.reachable_cells_explored_walkable += inside;
  }
  t.precision = ratio(t.walkable_cells_reachable, t.walkable_cells);
  t.recall_explored = ratio(t.reachable_cells_explored_walkable, t.reachable_cells_explored);
  t.recall_all = ratio(t.reachable_cells_walkable, t.reachable_cells);
  return t;
}

}  // namespace valerant
