#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <iostream>

#include "valerant/common/error.h"
#include "valerant/world/quake3/pk3_archive.h"
#include "valerant/world/quake3/reachable_floor.h"

#include "brush_world.h"
#include "openarena_data.h"

namespace valerant::quake3 {
namespace {

using Eigen::Vector3f;
using test::boxBrush;

// Two closed rooms side by side, floors at z = 0 and ceilings at `ceiling`:
// room 1 is x in [0, 256], y in [0, 128]; a solid wall x in [256, 272] separates it
// from room 2, x in [272, 528]. `floor` replaces the default floor slab.
std::vector<ConvexBrush> twoRooms(float ceiling = 128, std::vector<ConvexBrush> floor = {}) {
  if (floor.empty()) floor.push_back(boxBrush({-64, -64, -16}, {600, 192, 0}));
  std::vector<ConvexBrush> b = std::move(floor);
  b.push_back(boxBrush({-16, -16, 0}, {0, 144, ceiling}));     // west wall
  b.push_back(boxBrush({256, -16, 0}, {272, 144, ceiling}));   // dividing wall
  b.push_back(boxBrush({528, -16, 0}, {544, 144, ceiling}));   // east wall
  b.push_back(boxBrush({-16, -16, 0}, {544, 0, ceiling}));     // south wall
  b.push_back(boxBrush({-16, 128, 0}, {544, 144, ceiling}));   // north wall
  b.push_back(boxBrush({-16, -16, ceiling}, {544, 144, ceiling + 16}));
  return b;
}

size_t countAtHeight(const ReachableFloor& f, float z) {
  return std::count_if(f.cells.begin(), f.cells.end(),
                       [&](const Vector3f& c) { return std::abs(c.z() - z) < 1e-2f; });
}

// With 16-unit cells anchored at the spawn, the 30-unit hull fits at x = 16..240
// (15 columns) and y = 16..112 (7 rows) of room 1: 105 cells of 0.25 m^2.
TEST(ReachableFloor, FlatRoomIsFilledAndTheClosedRoomIsNot) {
  const CollisionModel m(twoRooms());
  const ReachableFloor f = floodFillReachableFloor(m, {128, 64, 24});
  EXPECT_EQ(f.cells.size(), 105u);
  EXPECT_DOUBLE_EQ(f.areaSquareMetres(), 26.25);
  EXPECT_EQ(countAtHeight(f, 0), 105u);
  for (const auto& c : f.cells) {
    EXPECT_GE(c.x(), 15);
    EXPECT_LE(c.x(), 241);
    EXPECT_GE(c.y(), 15);
    EXPECT_LE(c.y(), 113);
  }
}

TEST(ReachableFloor, CellSizeScalesTheArea) {
  const CollisionModel m(twoRooms());
  ReachableFloorParams p;
  p.cell_size = 32;
  const ReachableFloor f = floodFillReachableFloor(m, {128, 64, 24}, {}, p);
  EXPECT_EQ(f.cells.size(), 21u);  // x = 32..224 by 32, y = 32, 64, 96
  EXPECT_DOUBLE_EQ(f.areaSquareMetres(), 21.0);
}

TEST(ReachableFloor, SixteenUnitStepIsClimbed) {
  auto brushes = twoRooms();
  brushes.push_back(boxBrush({128, 0, 0}, {256, 128, 16}));
  const ReachableFloor f = floodFillReachableFloor(CollisionModel(brushes), {64, 64, 24});
  // Hulls at x >= 128 overlap the step and stand on it: 8 columns up, 7 down.
  EXPECT_EQ(f.cells.size(), 105u);
  EXPECT_EQ(countAtHeight(f, 16), 56u);
  EXPECT_EQ(countAtHeight(f, 0), 49u);
}

TEST(ReachableFloor, ThirtyTwoUnitLedgeIsNotClimbedButDroppedFrom) {
  auto brushes = twoRooms();
  brushes.push_back(boxBrush({128, 0, 0}, {256, 128, 32}));
  const CollisionModel m(brushes);
  const ReachableFloor below = floodFillReachableFloor(m, {64, 64, 24});
  EXPECT_EQ(below.cells.size(), 49u);
  EXPECT_EQ(countAtHeight(below, 0), 49u);
  const ReachableFloor above = floodFillReachableFloor(m, {192, 64, 56});
  EXPECT_EQ(above.cells.size(), 105u);
  EXPECT_EQ(countAtHeight(above, 32), 56u);
  EXPECT_EQ(countAtHeight(above, 0), 49u);
}

TEST(ReachableFloor, LowCeilingStillAllowsFlatWalking) {
  // 66 units of headroom: the hull (56) fits, also 9 units up where the game spawns
  // it, but cannot be stepped up by 18.
  const ReachableFloor f = floodFillReachableFloor(CollisionModel(twoRooms(66)), {128, 64, 24});
  EXPECT_EQ(f.cells.size(), 105u);
}

TEST(ReachableFloor, HoleIntoTheVoidIsNotCrossed) {
  // No floor for 96 < x < 160 and nothing below: hulls at x = 112..144 would fall
  // forever, so only x = 16..96 (6 columns) is reachable from x = 64.
  const CollisionModel m(twoRooms(128, {boxBrush({-64, -64, -16}, {96, 192, 0}),
                                        boxBrush({160, -64, -16}, {600, 192, 0})}));
  const ReachableFloor f = floodFillReachableFloor(m, {64, 64, 24});
  EXPECT_EQ(f.cells.size(), 42u);
}

TEST(ReachableFloor, NodeBoundIsRespected) {
  ReachableFloorParams p;
  p.max_nodes = 10;
  const ReachableFloor f = floodFillReachableFloor(CollisionModel(twoRooms()), {128, 64, 24}, {}, p);
  EXPECT_EQ(f.cells.size(), 10u);
}

TEST(ReachableFloor, BadSpawnsThrowNamingTheSpawn) {
  const CollisionModel m(twoRooms());
  try {
    floodFillReachableFloor(m, {264, 64, 24});  // inside the dividing wall
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("spawn point (264 64 24)"), std::string::npos) << e.what();
  }
  EXPECT_THROW(floodFillReachableFloor(m, {2000, 64, 24}), InputError);  // nothing below
}

// ------------------------------------------------------------------ real maps
BspMap loadMap(const std::string& name) {
  Pk3FileSystem fs;
  fs.mountDirectory(Pk3FileSystem::defaultDataDir());
  auto bytes = fs.read("maps/" + name + ".bsp");
  if (!bytes) throw InputError("maps/" + name + ".bsp", "not in the OpenArena data");
  return parseBsp(*bytes, name);
}

TEST(ReachableFloorOnMap, OaDm1AreaIsPlausible) {
  VALERANT_REQUIRE_OPENARENA();
  const auto map = loadMap("oa_dm1");
  const CollisionModel m = CollisionModel::fromBsp(map);
  const auto spawns = map.spawnPoints();
  ASSERT_FALSE(spawns.empty());
  const auto t0 = std::chrono::steady_clock::now();
  const ReachableFloor f = floodFillReachableFloor(m, spawns.front().origin);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << "oa_dm1: " << f.cells.size() << " cells, " << f.areaSquareMetres()
            << " m^2 reachable from the first spawn in " << seconds << " s\n";
  EXPECT_GT(f.areaSquareMetres(), 100);
  EXPECT_LT(f.areaSquareMetres(), 5000);
  for (const auto& c : f.cells) EXPECT_TRUE(m.bounds().contains(c)) << c.transpose();
}

TEST(ReachableFloorOnMap, PatchFloorsCarryThePlayer) {
  VALERANT_REQUIRE_OPENARENA();
  // Two wrackdm17 spawns (at x = -1344 and -1216) stand on a floor made only of
  // Bezier patches; without patch collision they would have no floor at all.
  const auto map = loadMap("wrackdm17");
  const CollisionModel m = CollisionModel::fromBsp(map);
  const PlayerHull hull;
  const float max_drop = ReachableFloorParams{}.max_drop;
  for (const auto& s : map.spawnPoints())
    EXPECT_TRUE(m.dropBox(s.origin + Vector3f(0, 0, 9), hull.mins, hull.maxs, max_drop))
        << s.origin.transpose();
  const ReachableFloor f = floodFillReachableFloor(m, {-1344, 704, 296});
  EXPECT_NEAR(f.cells.front().z(), 256, 1e-2);  // the patch floor, not the void below
  EXPECT_GT(f.areaSquareMetres(), 100);
}

}  // namespace
}  // namespace valerant::quake3
