// The goal move (goal_move.h) on the hand-built walled room (walled_room_grid.h): the
// farthest path cell in a free straight line, the turn to face it and the walk there.
#include <gtest/gtest.h>

#include <cmath>

#include "valerant/geometry/goal_move.h"
#include "walled_room_grid.h"

using namespace valerant;
using valerant::test::roomCell;

namespace {

Eigen::Vector2d at(double x, double y) { return {64 + x, 64 + y}; }

}  // namespace

TEST(GoalMove, StraightToTheFrontierWhenTheLineIsFree) {
  const CoverageGrid g = test::walledRoomGrid();
  const FrontierDistance d(g, {});
  // From (3, 0) facing +x (angle 0): the path (2,0), (1,0), (0,0) lies on one line;
  // its end is 3 cells behind: turn 180 degrees, walk 3 cells.
  const auto move = goalMove(g, {}, d, at(3, 0), 0.0, 8);
  ASSERT_TRUE(move);
  EXPECT_EQ(move->target, roomCell(0, 0));
  EXPECT_DOUBLE_EQ(move->turn_deg, 180.0);
  EXPECT_DOUBLE_EQ(move->walk_cells, 3.0);
  // From the cell's corner side (3, 0.4) facing +y (90 degrees): to (0, 0) is
  // (-3, -0.4), 3.0265 cells at 180 + 7.595 degrees: a turn of 97.595 degrees left.
  const auto off = goalMove(g, {}, d, at(3, 0.4), M_PI / 2, 8);
  ASSERT_TRUE(off);
  EXPECT_EQ(off->target, roomCell(0, 0));
  EXPECT_NEAR(off->walk_cells, std::hypot(3.0, 0.4), 1e-12);
  EXPECT_NEAR(off->turn_deg, 90.0 + std::atan2(0.4, 3.0) * 180 / M_PI, 1e-9);
}

TEST(GoalMove, AnObstacleInTheLineStopsAtAnEarlierPathCell) {
  CoverageGrid g = test::walledRoomGrid();
  for (int i = 0; i < 3; ++i) g.markObstaclePoint({2, 1, 0.5});  // a pillar at (2, 1)
  const FrontierDistance d(g, {});
  // From (4, 1) the path is (3,0), (2,0), (1,0), (0,0). The line to (0, 0), direction
  // (-4, -1) / sqrt 17, samples (2.06, 0.51) at 2 cells: cell (2, 1), the pillar, so its
  // ray is 1.5 cells of 4.12. The line to (1, 0), direction (-3, -1) / sqrt 10, samples
  // cells (4,1), (3,1), (3,1), (2,0), (2,0), (1,0) every half cell: free to 3.0 >=
  // sqrt 10 - 0.5. Facing +x: turn atan2(-1, -3) = -161.57 degrees.
  const auto move = goalMove(g, {}, d, at(4, 1), 0.0, 8);
  ASSERT_TRUE(move);
  EXPECT_EQ(move->target, roomCell(1, 0));
  EXPECT_NEAR(move->walk_cells, std::sqrt(10.0), 1e-12);
  EXPECT_NEAR(move->turn_deg, std::atan2(-1.0, -3.0) * 180 / M_PI, 1e-9);
  // One forward action of path, capped at 2 cells: the farthest is (2, 0).
  const auto short_move = goalMove(g, {}, d, at(4, 1), 0.0, 2);
  ASSERT_TRUE(short_move);
  EXPECT_EQ(short_move->target, roomCell(2, 0));
}

TEST(GoalMove, NoneWithoutAPath) {
  const CoverageGrid g = test::walledRoomGrid();
  const FrontierDistance cut(g, {roomCell(1, -1), roomCell(1, 0), roomCell(1, 1)});
  EXPECT_FALSE(goalMove(g, {roomCell(1, -1), roomCell(1, 0), roomCell(1, 1)}, cut, at(3, 0), 0.0, 8));
  const FrontierDistance d(g, {});
  EXPECT_FALSE(goalMove(g, {}, d, at(0, 0), 0.0, 8));  // standing on the frontier
}
