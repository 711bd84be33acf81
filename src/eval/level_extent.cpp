#include "valerant/eval/level_extent.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "valerant/world/quake3/units.h"

namespace valerant {

LevelExtent levelExtent(const quake3::ReachableFloor& reachable, const Eigen::Vector3f& spawn_origin,
                        const Config& config, const quake3::PlayerHull& hull) {
  LevelExtent e;
  e.reachable_m2 = reachable.areaSquareMetres();
  double farthest_units = 0;
  // The spawn's storey: the floor of the reachable cell under it (spawn points may float).
  double feet = spawn_origin.z() + hull.mins.z(), nearest = std::numeric_limits<double>::infinity();
  for (const auto& c : reachable.cells) {
    const double d = std::hypot(double(c.x() - spawn_origin.x()), double(c.y() - spawn_origin.y()));
    farthest_units = std::max(farthest_units, d);
    if (d < nearest) nearest = d, feet = c.z();
  }
  size_t same = 0, above = 0;
  for (const auto& c : reachable.cells) {
    const double rise = c.z() - feet;
    if (std::abs(rise) <= hull.step_height) ++same;
    else if (rise > 0) ++above;
  }
  if (!reachable.cells.empty()) {
    const double n = static_cast<double>(reachable.cells.size());
    e.spawn_storey_percent = 100.0 * same / n;
    e.above_percent = 100.0 * above / n;
    e.below_percent = 100.0 * (reachable.cells.size() - same - above) / n;
  }
  e.farthest_m = farthest_units / quake3::kUnitsPerMetre;
  const double cell_m = config.world.d_fwd_units / config.policy.cells_per_d_fwd / quake3::kUnitsPerMetre;
  e.grid_reach_m = (config.policy.grid_cells / 2 - 0.5) * cell_m;
  e.grid_cells_needed = 2 * static_cast<int>(std::ceil(e.farthest_m / cell_m + 0.5));
  e.fits = e.farthest_m <= e.grid_reach_m;
  return e;
}

}  // namespace valerant
