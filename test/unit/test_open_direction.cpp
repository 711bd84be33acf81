// Free rays, the opening O and the open direction (open_direction.h) on the
// hand-built walled room (walled_room_grid.h), from the agent's cell (3, 0).
#include <gtest/gtest.h>

#include <cmath>

#include "valerant/geometry/open_direction.h"
#include "walled_room_grid.h"

using namespace valerant;
using valerant::test::roomCell;

namespace {
constexpr double kDeg = M_PI / 180.0;
}

TEST(OpenDirection, FloorAngleOfADirection) {
  const CoverageGrid g = test::walledRoomGrid();
  EXPECT_NEAR(floorAngle(g, {1, 0, 0.3}), 0.0, 1e-12);       // along u, height ignored
  EXPECT_NEAR(floorAngle(g, {0, 2, 0}), 90 * kDeg, 1e-12);     // along v = n x u: a left turn
  EXPECT_NEAR(floorAngle(g, {-1, -1, 5}), -135 * kDeg, 1e-12);
}

TEST(OpenDirection, FreeRays) {
  const CoverageGrid g = test::walledRoomGrid();
  const Cell here = roomCell(3, 0);
  // East: samples at 0.5 and 1.0 lie in (4, 0), at 1.5 in the wall (5, 0).
  EXPECT_DOUBLE_EQ(freeRayCells(g, {}, here, 0.0, 100), 1.0);
  // North: (3, 1), then the wall at y = 2 from 1.5.
  EXPECT_DOUBLE_EQ(freeRayCells(g, {}, here, 90 * kDeg, 100), 1.0);
  // West: (2, 0) from 1.0, (1, 0) from 2.0, (0, 0) from 3.0, the unknown doorway at 4.0.
  EXPECT_DOUBLE_EQ(freeRayCells(g, {}, here, 180 * kDeg, 100), 3.5);
  EXPECT_DOUBLE_EQ(freeRayCells(g, {}, here, 180 * kDeg, 2), 2.0);  // capped
  // F at (1, 0) stops it at 1.5.
  EXPECT_DOUBLE_EQ(freeRayCells(g, {roomCell(1, 0)}, here, 180 * kDeg, 100), 1.5);
}

TEST(OpenDirection, OpeningIsTheShareOfAForwardActionAhead) {
  const CoverageGrid g = test::walledRoomGrid();
  // 8 cells per forward action: west 3.5 / 8, east 1 / 8.
  EXPECT_DOUBLE_EQ(opening(g, {}, roomCell(3, 0), 180 * kDeg), 3.5 / 8);
  EXPECT_DOUBLE_EQ(opening(g, {}, roomCell(3, 0), 0.0), 1.0 / 8);
}

TEST(OpenDirection, TurnsToTheMiddleOfTheLongestRays) {
  const CoverageGrid g = test::walledRoomGrid();
  // Every ray from 155 to 205 degrees runs 3.5 cells (it leaves the room's floor at x = -1,
  // below 155 it meets the wall at y = +-2 first): the middle of that run is 180.
  const auto west = openDirection(g, {}, roomCell(3, 0), 0.0, 72, 22.5);
  ASSERT_TRUE(west);
  EXPECT_DOUBLE_EQ(west->turn_deg, 180.0);
  EXPECT_DOUBLE_EQ(west->ray_cells, 3.5);
  // Facing west already (heading 180), turns under 22.5 degrees are no turn: the longest
  // remaining rays, 3.5, are the single rays 25 left and 25 right (absolute 205 and 155);
  // runs of equal width go to the first counter-clockwise from the heading: 25 left.
  const auto facing = openDirection(g, {}, roomCell(3, 0), 180 * kDeg, 72, 22.5);
  ASSERT_TRUE(facing);
  EXPECT_DOUBLE_EQ(facing->ray_cells, 3.5);
  EXPECT_DOUBLE_EQ(facing->turn_deg, 25.0);
  // Every cell around the agent's, and its own, blocked: nothing to turn to.
  const auto none = openDirection(g, {roomCell(3, 0), roomCell(2, 0), roomCell(2, 1), roomCell(2, -1), roomCell(3, 1),
                                      roomCell(3, -1), roomCell(4, 0), roomCell(4, 1), roomCell(4, -1)},
                                  roomCell(3, 0), 0.0, 72, 22.5);
  EXPECT_FALSE(none);
}

TEST(OpenDirection, TurnsBetweenAngles) {
  EXPECT_NEAR(cellAngle({3, 0}, {0, 0}), M_PI, 1e-12);
  EXPECT_NEAR(cellAngle({0, 0}, {1, 1}), M_PI / 4, 1e-12);
  EXPECT_NEAR(turnDeg(0.0, M_PI / 2), 90.0, 1e-9);
  EXPECT_NEAR(turnDeg(170 * kDeg, -170 * kDeg), 20.0, 1e-9);   // through 180, not -340
  EXPECT_NEAR(turnDeg(-170 * kDeg, 170 * kDeg), -20.0, 1e-9);
  EXPECT_NEAR(turnDeg(0.0, M_PI), 180.0, 1e-9);                // (-180, 180]
  EXPECT_NEAR(turnDeg(0.0, -M_PI), 180.0, 1e-9);
}
