#pragma once
// How an exported walkable area (walkable_area.h) agrees with the floor a Quake III
// player reaches by walking from the spawn (reachable_floor.h); engine world only, the
// ground truth never feeds an export. Compared in 2D on the floor, storeys merged,
// with reachable floor as the set of 16-unit cells holding a reachable player origin:
//  - precision: of the floor-grid cells whose centre lies in the walkable polygons, the
//    share whose centre lies in a reachable cell;
//  - recall in the explored region: of the reachable cells whose centre falls in a
//    floor-grid cell the map observed (floor or obstacle), the share whose centre lies
//    in the walkable polygons;
//  - recall over all reachable floor (bounded by how much the run explored).
// The SLAM map is tied to the BSP frame by `map_to_world_metres`, the Sim(3) of the
// committed camera centres onto their ground truth (as in episode_truth.h).
#include <Eigen/Core>

#include "valerant/eval/trajectory_metrics.h"
#include "valerant/map/map_frame.h"
#include "valerant/map/map_fusion.h"
#include "valerant/map/walkable_area.h"
#include "valerant/world/quake3/reachable_floor.h"

namespace valerant {

struct WalkableTruth {
  double precision = 0;
  double recall_explored = 0;
  double recall_all = 0;
  int walkable_cells = 0;               // floor-grid cells inside the polygons
  int walkable_cells_reachable = 0;
  int reachable_cells = 0;              // 2D reachable cells
  int reachable_cells_explored = 0;
  int reachable_cells_explored_walkable = 0;
  int reachable_cells_walkable = 0;
};

// `grid`: the floor grid the area was traced from; `spawn_origin`: the player origin
// the flood fill started from (its cells are centred on it), game units.
WalkableTruth evaluateWalkableTruth(const WalkableArea& walkable, const FloorGrid& grid, const MapFrame& frame,
                                    const Sim3& map_to_world_metres, const quake3::ReachableFloor& reachable,
                                    const Eigen::Vector3f& spawn_origin);

}  // namespace valerant
