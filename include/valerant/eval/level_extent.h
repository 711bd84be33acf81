#pragma once
// Whether the exploration grid (coverage_grid.h) reaches over a whole level: the
// reachable floor's farthest horizontal distance from a spawn against the grid's reach.
// The grid is anchored at the spawn, its cells d_fwd / cells_per_d_fwd wide (1 m with
// the paper's values), the anchor at the centre of cell (size/2, size/2), and turned
// with the spawn's heading; so whatever the heading it holds every point within
// (size/2 - 1/2) cells of the anchor (63.5 m for 128 cells).
// The storeys: the share of the reachable floor (by cells) whose floor lies within one
// step (the hull's step_height, 18 units) of the floor under the spawn (of the reachable
// cell nearest it; spawn points may float), and above or below that: what an agent
// that never changes storey can observe at most.
#include <Eigen/Core>

#include "valerant/config/config.h"
#include "valerant/world/quake3/player_hull.h"
#include "valerant/world/quake3/reachable_floor.h"

namespace valerant {

struct LevelExtent {
  double reachable_m2 = 0;
  double farthest_m = 0;       // horizontal distance from the spawn to the farthest reachable floor
  double grid_reach_m = 0;     // the grid holds every point this close to its anchor
  int grid_cells_needed = 0;   // the least even grid_cells whose reach is >= farthest_m
  bool fits = false;           // farthest_m <= grid_reach_m
  double spawn_storey_percent = 0, above_percent = 0, below_percent = 0;
};

// `spawn_origin`: game units, as the reachable floor's cells; `config`: the grid's
// policy.grid_cells, policy.cells_per_d_fwd and world.d_fwd_units.
LevelExtent levelExtent(const quake3::ReachableFloor& reachable, const Eigen::Vector3f& spawn_origin,
                        const Config& config, const quake3::PlayerHull& hull = {});

}  // namespace valerant
