#pragma once
// Ground truth: the floor a Quake III player can walk to from a spawn point, by a
// flood fill of the player hull over (xy cell, floor height) nodes. A step to a
// neighbour cell may climb at most one STEPSIZE and may drop any height (falling
// is allowed; climbing back is not implied). Jump pads, teleporters and jumps are
// ignored: the set is what walking reaches.
#include <Eigen/Core>
#include <vector>

#include "valerant/world/quake3/collision_model.h"
#include "valerant/world/quake3/player_hull.h"

namespace valerant::quake3 {

struct ReachableFloorParams {
  float cell_size = 16.f;   // game units
  float max_drop = 1024.f;  // deepest fall followed
  int max_nodes = 2000000;  // safety bound for leaky maps
};

struct ReachableFloor {
  float cell_size = 16.f;
  // Centre of every reachable cell at the height of the floor under it (feet level).
  std::vector<Eigen::Vector3f> cells;
  double areaSquareMetres() const;  // 32 game units = 1 m
};

// `spawn_origin` is a player origin (24 above the feet). Throws InputError if the
// spawn is in solid or has no floor beneath it.
ReachableFloor floodFillReachableFloor(const CollisionModel& model,
                                       const Eigen::Vector3f& spawn_origin,
                                       const PlayerHull& hull = {},
                                       const ReachableFloorParams& params = {});

}  // namespace valerant::quake3
