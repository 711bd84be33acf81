#include "valerant/world/quake3/reachable_floor.h"

#include <array>
#include <cmath>
#include <sstream>
#include <unordered_map>

#include "valerant/common/error.h"
#include "valerant/world/quake3/units.h"

namespace valerant::quake3 {
namespace {

using Eigen::Vector3f;

// Two resting heights in one cell closer than this are the same floor (a slope or
// rounding), farther apart they are different storeys.
constexpr float kSameFloorTolerance = 4.f;
// Longest horizontal sub-step when checking a move for walls in the way.
constexpr float kMaxSubStep = 8.f;

struct Node {
  int ix, iy;
  float z;       // resting player origin
  int next = -1;  // next node of the same (ix, iy) cell: other storeys
};

uint64_t cellKey(int ix, int iy) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(ix)) << 32) | static_cast<uint32_t>(iy);
}

std::string describeSpawn(const Vector3f& p) {
  std::ostringstream s;
  s << "spawn point (" << p.x() << " " << p.y() << " " << p.z() << ")";
  return s.str();
}

std::string noFloorWithin(float max_drop) {
  std::ostringstream s;
  s << "no floor within " << max_drop << " units below";
  return s.str();
}

}  // namespace

double ReachableFloor::areaSquareMetres() const {
  const double side_m = cell_size / kUnitsPerMetre;
  return static_cast<double>(cells.size()) * side_m * side_m;
}

ReachableFloor floodFillReachableFloor(const CollisionModel& model, const Vector3f& spawn_origin,
                                       const PlayerHull& hull, const ReachableFloorParams& params) {
  if (!(params.cell_size > 0))
    throw InputError("reachable floor cell_size " + std::to_string(params.cell_size), "must be positive");
  const Vector3f& mins = hull.mins;
  const Vector3f& maxs = hull.maxs;
  // The game spawns the player 9 units above the spawn point and lets it fall
  // (g_client.c), so spawn points may sit slightly in a floor or clip brush.
  const Vector3f start = spawn_origin + Vector3f(0, 0, 9);
  if (model.boxInSolid(start, mins, maxs))
    throw InputError(describeSpawn(spawn_origin), "the player hull is in solid");
  const std::optional<float> spawn_z = model.dropBox(start, mins, maxs, params.max_drop);
  if (!spawn_z)
    throw InputError(describeSpawn(spawn_origin), noFloorWithin(params.max_drop));

  const float cell = params.cell_size;
  const Vector3f lift(0, 0, hull.step_height);
  const int sub_steps = std::max(1, static_cast<int>(std::ceil(cell / kMaxSubStep)));
  const Eigen::AlignedBox3f world = model.bounds();
  auto originOf = [&](int ix, int iy, float z) {
    return Vector3f(spawn_origin.x() + ix * cell, spawn_origin.y() + iy * cell, z);
  };
  // The hull can move in a straight line from `from` to `to` (same height) without
  // entering a wall; the starting box is known to be free.
  auto pathFree = [&](const Vector3f& from, const Vector3f& to) {
    for (int k = 1; k <= sub_steps; ++k)
      if (model.boxInSolid(from + (to - from) * (static_cast<float>(k) / sub_steps), mins, maxs))
        return false;
    return true;
  };

  std::vector<Node> nodes;
  std::unordered_map<uint64_t, int> first_node_of_cell;
  auto addNode = [&](int ix, int iy, float z) {
    if (nodes.size() >= static_cast<size_t>(params.max_nodes)) return;
    auto [it, inserted] = first_node_of_cell.try_emplace(cellKey(ix, iy), static_cast<int>(nodes.size()));
    if (!inserted) {
      int last = it->second;
      for (int i = last; i >= 0; i = nodes[i].next) {
        if (std::abs(nodes[i].z - z) < kSameFloorTolerance) return;
        last = i;
      }
      nodes[last].next = static_cast<int>(nodes.size());
    }
    nodes.push_back({ix, iy, z});
  };
  addNode(0, 0, *spawn_z);

  // Breadth-first: `nodes` doubles as the queue. Like the game's PM_StepSlideMove a
  // move is tried stepped up by STEPSIZE first, then flat when a low ceiling blocks
  // the stepped box; either way the hull then falls onto whatever floor is below.
  // (The game clips the step-up at the ceiling; we only try the full step or none.)
  constexpr std::array<std::array<int, 2>, 4> kDirections{{{1, 0}, {-1, 0}, {0, 1}, {0, -1}}};
  for (size_t i = 0; i < nodes.size(); ++i) {
    const Node node = nodes[i];
    const Vector3f here = originOf(node.ix, node.iy, node.z);
    const bool can_step_up = !model.boxInSolid(here + lift, mins, maxs);
    for (const auto& [dx, dy] : kDirections) {
      const int ix = node.ix + dx, iy = node.iy + dy;
      const Vector3f there = originOf(ix, iy, node.z);
      if (there.x() < world.min().x() || there.x() > world.max().x() ||
          there.y() < world.min().y() || there.y() > world.max().y())
        continue;
      std::optional<float> z;
      if (can_step_up && pathFree(here + lift, there + lift))
        z = model.dropBox(there + lift, mins, maxs, hull.step_height + params.max_drop);
      else if (pathFree(here, there))
        z = model.dropBox(there, mins, maxs, params.max_drop);
      if (z) addNode(ix, iy, *z);  // no floor: a fall into the void
    }
  }

  ReachableFloor floor;
  floor.cell_size = cell;
  floor.cells.reserve(nodes.size());
  for (const Node& n : nodes) floor.cells.push_back(originOf(n.ix, n.iy, n.z + mins.z()));
  return floor;
}

}  // namespace valerant::quake3
