// The coverage grid's surface layer (surface_layer.h): each cell's surface height from
// the points in it, faces, storeys, and the steps paths may take between cells; then the
// whole-level goal climbing a staircase on a grid that uses it.
#include <gtest/gtest.h>

#include "valerant/geometry/coverage_grid.h"
#include "valerant/geometry/frontier_distance.h"
#include "valerant/geometry/surface_layer.h"

using namespace valerant;

namespace {

// Three points (policy.obstacle_min_points) at each height.
void addPoints(SurfaceLayer& layer, size_t cell, std::initializer_list<double> heights) {
  for (double h : heights)
    for (int i = 0; i < 3; ++i) layer.addPoint(cell, h);
}

}  // namespace

TEST(SurfaceLayer, HeightIsTheTopOfTheTopRun) {
  SurfaceLayer layer(0.7, 3);
  // A floor: bin floor((0.02 + 12.8) / 0.1) = 128, whose top is -12.8 + 129 * 0.1 = 0.1.
  addPoints(layer, 1, {0.02});
  ASSERT_TRUE(layer.height(1));
  EXPECT_NEAR(*layer.height(1), 0.1, 1e-9);
  // A stair: riser points 0.05 and 0.2, tread 0.34: bins 128, 130, 131, a run of 0.3
  // (under 0.7): a surface at the top of bin 131, 0.4.
  addPoints(layer, 2, {0.05, 0.2, 0.34});
  ASSERT_TRUE(layer.height(2));
  EXPECT_NEAR(*layer.height(2), 0.4, 1e-9);
  // A wall: points every 0.3 from the floor to 1.15, bins 128 to 139 with gaps of 2
  // bins (0.2, within kRunGap 0.3): a run of 1.1, taller than 0.7: a face, no height.
  addPoints(layer, 3, {0.02, 0.3, 0.6, 0.9, 1.15});
  EXPECT_FALSE(layer.height(3));
  EXPECT_TRUE(layer.seen(3));
  // Two storeys: a floor 4.5 below (bin 83) and one at 0.02 (bin 128), 44 bins apart:
  // the top run is the upper floor alone.
  addPoints(layer, 4, {-4.5, 0.02});
  ASSERT_TRUE(layer.height(4));
  EXPECT_NEAR(*layer.height(4), 0.1, 1e-9);
  // Two points are no evidence (obstacle_min_points 3).
  layer.addPoint(5, 1.0);
  layer.addPoint(5, 1.0);
  EXPECT_FALSE(layer.seen(5));
  EXPECT_FALSE(layer.height(5));
  EXPECT_FALSE(layer.seen(99));  // never touched
  // Where the agent stood, its floor is the height, whatever else the cell holds; the
  // lowest of several.
  layer.addStand(3, 0.02);
  layer.addStand(3, -0.01);
  ASSERT_TRUE(layer.height(3));
  EXPECT_DOUBLE_EQ(*layer.height(3), -0.01);
}

TEST(SurfaceLayer, StepsRiseAtMostMaxRise) {
  SurfaceLayer layer(0.7, 3);
  addPoints(layer, 1, {0.02});   // 0.1
  addPoints(layer, 2, {0.55});   // bin 133: 0.6, 0.5 above cell 1
  addPoints(layer, 3, {0.95});   // bin 137: 1.0, 0.9 above cell 1
  addPoints(layer, 4, {0.02, 0.3, 0.6, 0.9, 1.15});  // a face
  EXPECT_TRUE(layer.step(1, 2));
  EXPECT_TRUE(layer.step(2, 1));
  EXPECT_FALSE(layer.step(1, 3));  // 0.9 up
  EXPECT_TRUE(layer.step(3, 1));   // 0.9 down: a drop off a ledge
  EXPECT_TRUE(layer.step(2, 3));   // 0.4
  EXPECT_FALSE(layer.step(1, 4));
  EXPECT_FALSE(layer.step(1, 7));  // unknown
}

TEST(SurfaceLayer, TheGoalClimbsAStaircaseTheFlatModelTakesForAWall) {
  // Unit cells and heights (anchor floor z = 0, eye height 1): cell (64 + x, 64 + y)
  // holds the floor point (x, y). A corridor y = 0 walled at y = +-1: the agent stands
  // at x = 0, floor at x = 1, stairs up at x = 2, 3, 4 (surfaces 0.5, 1.0, 1.5), unknown
  // beyond at x = 5, so the frontier is x = 4.
  FloorPlane anchor;
  anchor.q = {0, 0, 0};
  anchor.n = {0, 0, 1};
  anchor.c = {0, 0, 1};
  PolicyConfig config;
  config.max_cell_rise = 0.7;
  auto build = [&](const PolicyConfig& c, double third_step) {
    CoverageGrid g(c, anchor, Eigen::Vector3d::UnitX(), 8.0);
    auto points = [&](double x, double y, std::initializer_list<double> heights) {
      for (double h : heights)
        for (int i = 0; i < 3; ++i) {
          const Eigen::Vector3d p(x, y, h);
          g.markSurfacePoint(p);
          if (h < 0.18) g.markObservedFloor(p); else if (h <= 1.19) g.markObstaclePoint(p);
        }
    };
    g.markVisited({0, 0, 1});
    points(1, 0, {0.02});
    points(2, 0, {0.45});
    points(3, 0, {0.95});
    points(4, 0, {third_step});
    for (int x = -1; x <= 5; ++x) {
      points(x, 1, {0.02, 0.3, 0.6, 0.9, 1.15});
      points(x, -1, {0.02, 0.3, 0.6, 0.9, 1.15});
    }
    points(-1, 0, {0.02, 0.3, 0.6, 0.9, 1.15});
    return g;
  };
  const Cell start{64, 64};
  const CoverageGrid stairs = build(config, 1.45);
  EXPECT_TRUE(stairs.unknown({69, 64}));
  EXPECT_FALSE(stairs.walkable({64, 65}));  // the corridor's wall
  const FrontierDistance d(stairs, {});
  EXPECT_TRUE(d.isGoalFrontier({68, 64}));
  EXPECT_DOUBLE_EQ(d.at(start), 4.0);  // up the stairs
  // A last step of 0.9 (surface 1.9 after 1.0) is too high: no frontier reachable.
  const CoverageGrid ledge = build(config, 1.85);
  EXPECT_EQ(FrontierDistance(ledge, {}).at(start), FrontierDistance::kUnreachable);
  // A pit instead: x = 2, 3, 4 at -0.5, -1.0 and -3.0: walking down is falling, D = 4
  // from the agent; from the pit's frontier x = 4 back up to x = 2 (2 up, then 0.5) no.
  const CoverageGrid pit = [&] {
    CoverageGrid g(config, anchor, Eigen::Vector3d::UnitX(), 8.0);
    auto points = [&](double x, double y, std::initializer_list<double> heights) {
      for (double h : heights)
        for (int i = 0; i < 3; ++i) g.markSurfacePoint({x, y, h});
    };
    g.markVisited({0, 0, 1});
    points(1, 0, {0.02});
    points(2, 0, {-0.55});
    points(3, 0, {-1.05});
    points(4, 0, {-3.05});
    for (int x = -1; x <= 5; ++x) {
      points(x, 1, {-3.05, -2.5, -2.0, -1.5, -1.0, -0.5, 0.02, 0.3, 0.6, 0.9, 1.15});
      points(x, -1, {-3.05, -2.5, -2.0, -1.5, -1.0, -0.5, 0.02, 0.3, 0.6, 0.9, 1.15});
    }
    points(-1, 0, {0.02, 0.3, 0.6, 0.9, 1.15});
    return g;
  }();
  const FrontierDistance down(pit, {});
  EXPECT_DOUBLE_EQ(down.at(start), 4.0);
  EXPECT_FALSE(pit.traversable({68, 64}, {67, 64}));  // 2.0 back up
  // The flat model takes the first step (0.45 over the floor) for an obstacle.
  PolicyConfig flat;
  const CoverageGrid flat_grid = build(flat, 1.45);
  EXPECT_FALSE(flat_grid.walkable({66, 64}));
  EXPECT_EQ(FrontierDistance(flat_grid, {}).at(start), FrontierDistance::kUnreachable);
}
