// The whole-level goal (frontier_distance.h) on a hand-built walled room
// (walled_room_grid.h): obstacle-aware frontiers, the path distance field and G.
#include <gtest/gtest.h>

#include <cmath>

#include "valerant/geometry/frontier_distance.h"
#include "walled_room_grid.h"

using namespace valerant;
using valerant::test::roomCell;

TEST(CoverageGrid, ObstacleLayerNeedsEnoughPoints) {
  CoverageGrid g = test::walledRoomGrid();
  EXPECT_TRUE(g.obstacle(roomCell(5, 0)));
  EXPECT_FALSE(g.walkable(roomCell(5, 0)));
  EXPECT_FALSE(g.unknown(roomCell(5, 0)));
  EXPECT_TRUE(g.unknown(roomCell(-1, 0)));
  g.markObstaclePoint({-1, 0, 0.5});
  g.markObstaclePoint({-1, 0, 0.5});
  EXPECT_FALSE(g.obstacle(roomCell(-1, 0)));  // 2 points, policy.obstacle_min_points is 3
  EXPECT_TRUE(g.unknown(roomCell(-1, 0)));    // a stray point or two is no evidence
  g.markObstaclePoint({-1, 0, 0.5});
  EXPECT_TRUE(g.obstacle(roomCell(-1, 0)));
}

TEST(FrontierDistance, AWallIsNoFrontier) {
  const CoverageGrid g = test::walledRoomGrid();
  const FrontierDistance d(g, {});
  // The paper's frontier (C_front) counts every floor cell beside a never-seen-as-floor
  // cell, walls included; the goal frontier only the doorway's neighbour.
  EXPECT_TRUE(g.isFrontier(roomCell(4, 0)));
  EXPECT_FALSE(d.isGoalFrontier(roomCell(4, 0)));
  EXPECT_FALSE(d.isGoalFrontier(roomCell(0, 1)));
  EXPECT_TRUE(d.isGoalFrontier(roomCell(0, 0)));
  int frontiers = 0;
  for (int i = 0; i < g.size(); ++i)
    for (int j = 0; j < g.size(); ++j) frontiers += d.isGoalFrontier({i, j});
  EXPECT_EQ(frontiers, 1);
  EXPECT_EQ(d.goalFrontierCells(), 1);
  EXPECT_EQ(FrontierDistance(g, {roomCell(0, 0)}).goalFrontierCells(), 0);  // the doorway in F
}

TEST(FrontierDistance, PathDistanceField) {
  const CoverageGrid g = test::walledRoomGrid();
  const FrontierDistance d(g, {});
  EXPECT_DOUBLE_EQ(d.at(roomCell(0, 0)), 0.0);
  EXPECT_DOUBLE_EQ(d.at(roomCell(3, 0)), 3.0);                   // three straight steps
  EXPECT_DOUBLE_EQ(d.at(roomCell(1, 1)), std::sqrt(2.0));        // one diagonal
  EXPECT_DOUBLE_EQ(d.at(roomCell(4, 1)), 3.0 + std::sqrt(2.0));  // three straight, one diagonal
  EXPECT_EQ(d.at(roomCell(5, 0)), FrontierDistance::kUnreachable);   // a wall
  EXPECT_EQ(d.at(roomCell(-2, 0)), FrontierDistance::kUnreachable);  // unknown
  EXPECT_EQ(d.at({-1, 0}), FrontierDistance::kUnreachable);          // outside the grid
}

TEST(FrontierDistance, GoalTermOfCandidates) {
  const CoverageGrid g = test::walledRoomGrid();
  const FrontierDistance d(g, {});
  const Cell start = roomCell(3, 0);
  // Two cells toward the doorway: G = (3 - 1) / 8.
  EXPECT_DOUBLE_EQ(d.goalTerm(start, roomCell(1, 0)), 0.25);
  // Into the far corner: G = (3 - (3 + sqrt 2)) / 8, away from the goal.
  EXPECT_DOUBLE_EQ(d.goalTerm(start, roomCell(4, 1)), -std::sqrt(2.0) / 8);
  // Through the doorway into unknown space: the goal reached, G = 3 / 8.
  EXPECT_DOUBLE_EQ(d.goalTerm(start, roomCell(-2, 0)), 3.0 / 8);
  // Into the wall: no distance there, G = 0 (the collision tests judge it).
  EXPECT_DOUBLE_EQ(d.goalTerm(start, roomCell(5, 0)), 0.0);
}

TEST(FrontierDistance, FailedRegionDetoursOrCutsOff) {
  const CoverageGrid g = test::walledRoomGrid();
  // F holds (2, 0): the path from (3, 0) goes round it, (0,0)-(1,0)-(2,1)-(3,0).
  const FrontierDistance detour(g, {roomCell(2, 0)});
  EXPECT_DOUBLE_EQ(detour.at(roomCell(3, 0)), 1.0 + 2.0 * std::sqrt(2.0));
  // F across the room at x = 1: no frontier reachable, G = 0 for every candidate.
  const FrontierDistance cut(g, {roomCell(1, -1), roomCell(1, 0), roomCell(1, 1)});
  EXPECT_EQ(cut.at(roomCell(3, 0)), FrontierDistance::kUnreachable);
  EXPECT_DOUBLE_EQ(cut.goalTerm(roomCell(3, 0), roomCell(-2, 0)), 0.0);
  // A frontier inside F is none.
  const FrontierDistance doorway_failed(g, {roomCell(0, 0)});
  EXPECT_FALSE(doorway_failed.isGoalFrontier(roomCell(0, 0)));
}

// [ours] dead_pocket.cross_failed: F is no goal but no wall either.
TEST(FrontierDistance, FailedRegionCrossedHoldsNoGoal) {
  const CoverageGrid g = test::walledRoomGrid();
  // F across the room at x = 1, crossed: from (3, 0) three straight steps to the
  // doorway's frontier, as without F, and a candidate toward it gains G = (3 - 1) / 8.
  const FrontierDistance crossed(g, {}, {roomCell(1, -1), roomCell(1, 0), roomCell(1, 1)});
  EXPECT_DOUBLE_EQ(crossed.at(roomCell(3, 0)), 3.0);
  EXPECT_DOUBLE_EQ(crossed.goalTerm(roomCell(3, 0), roomCell(1, 0)), 0.25);
  // The doorway's frontier in F is no goal: nothing is left to reach.
  const FrontierDistance doorway_failed(g, {}, {roomCell(0, 0)});
  EXPECT_FALSE(doorway_failed.isGoalFrontier(roomCell(0, 0)));
  EXPECT_EQ(doorway_failed.goalFrontierCells(), 0);
  EXPECT_EQ(doorway_failed.at(roomCell(3, 0)), FrontierDistance::kUnreachable);
}

TEST(FrontierDistance, WaypointFollowsThePathIntoTheUnknown) {
  const CoverageGrid g = test::walledRoomGrid();
  const FrontierDistance d(g, {});
  // From (3, 0) the path runs west to the frontier (0, 0), 3 cells; with room for it,
  // the waypoint is the unknown doorway beyond.
  EXPECT_EQ(d.waypoint(roomCell(3, 0), 8), roomCell(-1, 0));
  // With 2 cells of path, it stops at (1, 0).
  EXPECT_EQ(d.waypoint(roomCell(3, 0), 2), roomCell(1, 0));
  // From the far corner (4, 1), the first step is the diagonal to (3, 0).
  EXPECT_EQ(d.waypoint(roomCell(4, 1), 1), roomCell(3, 0));
  // Cut off by F: none.
  const FrontierDistance cut(g, {roomCell(1, -1), roomCell(1, 0), roomCell(1, 1)});
  EXPECT_FALSE(cut.waypoint(roomCell(3, 0), 8));
}

TEST(FrontierDistance, PathDescendsToTheFrontier) {
  const CoverageGrid g = test::walledRoomGrid();
  const FrontierDistance d(g, {});
  // From the far corner (4, 1): the diagonal to (3, 0) (D 3 against 3 + sqrt 2 for
  // (3, 1)), then straight west to the frontier (0, 0), where the path ends.
  EXPECT_EQ(d.path(roomCell(4, 1), 8),
            (std::vector<Cell>{roomCell(3, 0), roomCell(2, 0), roomCell(1, 0), roomCell(0, 0)}));
  // At most 2 cells of path: sqrt 2 + 1 reaches 2 after the second cell.
  EXPECT_EQ(d.path(roomCell(4, 1), 2), (std::vector<Cell>{roomCell(3, 0), roomCell(2, 0)}));
  EXPECT_TRUE(d.path(roomCell(0, 0), 8).empty());  // on the frontier
  const FrontierDistance cut(g, {roomCell(1, -1), roomCell(1, 0), roomCell(1, 1)});
  EXPECT_TRUE(cut.path(roomCell(3, 0), 8).empty());  // none reachable
}
