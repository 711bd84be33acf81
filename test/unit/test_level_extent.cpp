// Whether the exploration grid reaches over a level, on a hand-made reachable floor.
#include <gtest/gtest.h>

#include "valerant/eval/level_extent.h"

using namespace valerant;

TEST(LevelExtent, FarthestReachableFloorAgainstTheGridsReach) {
  quake3::ReachableFloor floor;
  floor.cell_size = 16;
  // Spawn at (32, 32); floor 20 m east of it and 30 m (3-4-5: 18 m by 24 m) north-west.
  floor.cells = {{32 + 640, 32, 0}, {32 - 576, 32 + 768, 100}, {32, 32, 0}};
  Config config;  // 128 cells of 256 / 8 = 32 units: 1 m
  LevelExtent e = levelExtent(floor, {32, 32, 24}, config);
  EXPECT_DOUBLE_EQ(e.farthest_m, 30.0);
  EXPECT_DOUBLE_EQ(e.grid_reach_m, 63.5);        // (128 / 2 - 0.5) cells of 1 m
  EXPECT_EQ(e.grid_cells_needed, 62);            // 2 * ceil(30 + 0.5): a reach of 30.5 m
  EXPECT_TRUE(e.fits);
  EXPECT_DOUBLE_EQ(e.reachable_m2, 3 * 0.25);    // three cells of 0.5 m x 0.5 m
  config.policy.grid_cells = 40;                 // reach 19.5 m
  e = levelExtent(floor, {32, 32, 24}, config);
  EXPECT_DOUBLE_EQ(e.grid_reach_m, 19.5);
  EXPECT_FALSE(e.fits);
}

TEST(LevelExtent, StoreysAgainstTheSpawnsFeet) {
  quake3::ReachableFloor floor;
  // The spawn floats at z 80 over the cell (0, 0) whose floor is 0: floors at 0 and 16
  // are on its storey (within the 18-unit step), 40 above, -100 below.
  floor.cells = {{0, 0, 0}, {16, 0, 16}, {32, 0, 40}, {48, 0, -100}};
  const LevelExtent e = levelExtent(floor, {2, 0, 80}, Config{});
  EXPECT_DOUBLE_EQ(e.spawn_storey_percent, 50.0);
  EXPECT_DOUBLE_EQ(e.above_percent, 25.0);
  EXPECT_DOUBLE_EQ(e.below_percent, 25.0);
}
