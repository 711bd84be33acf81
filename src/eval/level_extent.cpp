#include "valerant/eval/level_extent.h"

#include <algorithm>
#include <cmath>

#include "valerant/world/quake3/units.h"

namespace valerant {

LevelExtent levelExtent(const quake3::ReachableFloor& reachable, const Eigen::Vector3f& spawn_origin,
                        const Config& config) {
  LevelExtent e;
  e.reachable_m2 = reachable.areaSquareMetres();
  double farthest_units = 0;
  for (const auto& c : reachable.cells)
    farthest_units = std::max(farthest_units, std::hypot(double(c.x() - spawn_origin.x()), double(c.y() - spawn_origin.y())));
  e.farthest_m = farthest_units / quake3::kUnitsPerMetre;
  const double cell_m = config.world.d_fwd_units / config.policy.cells_per_d_fwd / quake3::kUnitsPerMetre;
  e.grid_reach_m = (config.policy.grid_cells / 2 - 0.5) * cell_m;
  e.grid_cells_needed = 2 * static_cast<int>(std::ceil(e.farthest_m / cell_m + 0.5));
  e.fits = e.farthest_m <= e.grid_reach_m;
  return e;
}

}  // namespace valerant
