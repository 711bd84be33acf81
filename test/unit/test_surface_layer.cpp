// The coverage grid's surface layer (surface_layer.h): each cell's surface height from
// the points in it, faces, storeys, and the steps paths may take between cells; then the
// whole-level goal climbing a staircase on a grid that uses it.
#include <gtest/gtest.h>

#include "unit_grid.h"
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

using test::unitAnchor;  // cell (64 + x, 64 + y) holds the floor point (x, y)

PolicyConfig surfaceConfig() {
  PolicyConfig config;
  config.max_cell_rise = 0.7;
  return config;
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
  const FloorPlane anchor = unitAnchor();
  PolicyConfig config = surfaceConfig();
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

TEST(SurfaceLayer, CarvingDropsBinsMoreRaysCrossedThanPointsFill) {
  // A floor cell filled with scatter: points 0.02, 0.25, 0.5, 0.75, 0.95 (bins 128, 130,
  // 133, 135, 137; gaps of at most 2 bins): one run of 0.9, a face.
  auto scattered = [](SurfaceLayer& layer) { addPoints(layer, 1, {0.02, 0.25, 0.5, 0.75, 0.95}); };
  SurfaceLayer plain(0.7, 3);
  scattered(plain);
  plain.addPass(1, 0.45, 1.05);  // ignored without carving
  EXPECT_FALSE(plain.height(1));
  // Four rays crossed it between 0.45 and 1.05 (bins 132 to 138): at ratio 1, bins 133,
  // 135 and 137 (3 points, 4 rays) drop out; the run is 128 and 130, whose top is
  // -12.8 + 131 * 0.1 = 0.3.
  SurfaceLayer carved(0.7, 3, 1.0);
  scattered(carved);
  for (int i = 0; i < 4; ++i) carved.addPass(1, 1.05, 0.45);  // either order
  ASSERT_TRUE(carved.height(1));
  EXPECT_NEAR(*carved.height(1), 0.3, 1e-9);
  // At ratio 0.5, 3 points outweigh 0.5 * 4 rays: the face stays.
  SurfaceLayer lenient(0.7, 3, 0.5);
  scattered(lenient);
  for (int i = 0; i < 4; ++i) lenient.addPass(1, 0.45, 1.05);
  EXPECT_FALSE(lenient.height(1));
  // A cell whose every point was crossed is still seen, with no surface.
  addPoints(carved, 2, {0.5});
  for (int i = 0; i < 4; ++i) carved.addPass(2, 0.45, 0.55);
  EXPECT_TRUE(carved.seen(2));
  EXPECT_FALSE(carved.height(2));
}

TEST(SurfaceLayer, SaturatingCountsHalveTheWholeCell) {
  SurfaceLayer layer(0.7, 3);
  // 4 points at 0.5 (bin 133) over a floor at 0.02 (bin 128), 4 empty bins apart (more
  // than kRunGap): the top run is bin 133 alone, height 0.6.
  for (int i = 0; i < 4; ++i) layer.addPoint(1, 0.5);
  for (int i = 0; i < 65535; ++i) layer.addPoint(1, 0.02);
  ASSERT_TRUE(layer.height(1));
  EXPECT_NEAR(*layer.height(1), 0.6, 1e-9);
  // The 65536th floor point halves the cell: bin 128 holds 32767 + 1, bin 133 holds 2,
  // under min_points 3: the surface is the floor's bin, top 0.1.
  layer.addPoint(1, 0.02);
  ASSERT_TRUE(layer.height(1));
  EXPECT_NEAR(*layer.height(1), 0.1, 1e-9);
}

TEST(SurfaceLayer, RaysFromTheEyeCarveTheScatterBeforeAWall) {
  // Unit cells (as above): the eye at (0, 0, 1) over the anchor floor z = 0, which is
  // also its keyframe's floor, so own heights are z. A wall at x = 4 (points 0.02, 0.3,
  // 0.6, 0.9, 1.15, three each) and, at x = 2, floor points with the wall's scatter
  // (0.02, 0.25, 0.5, 0.75, 0.95: a face, as in the test above).
  const FloorPlane anchor = unitAnchor();
  PolicyConfig config = surfaceConfig();
  auto build = [&](double carving_ratio) {
    PolicyConfig c = config;
    c.surface_carving_ratio = carving_ratio;
    CoverageGrid g(c, anchor, Eigen::Vector3d::UnitX(), 8.0);
    const Eigen::Vector3d eye(0, 0, 1);
    auto points = [&](double x, std::initializer_list<double> heights) {
      for (double h : heights)
        for (int i = 0; i < 3; ++i) {
          g.markSurfacePoint({x, 0, h});
          g.markSurfaceRay(eye, {x, 0, h}, h, 0.18);
        }
    };
    points(2, {0.02, 0.25, 0.5, 0.75, 0.95});
    points(4, {0.02, 0.3, 0.6, 0.9, 1.15});
    return g;
  };
  // Cell x = 2 spans x 1.5 to 2.5, t 0.375 to 0.625 of each ray to the wall. Ray to
  // height h crosses it from 1 + 0.375 (h - 1) down to 1 + 0.625 (h - 1):
  //   h 0.02 (stops at own height 0.18, t 0.837, beyond the cell): 0.6325-0.3875, bins 131-134
  //   h 0.3: 0.7375-0.5625, bins 133-135;  h 0.6: 0.85-0.75, bins 135-136
  //   h 0.9: 0.9625-0.9375, bin 137;  h 1.15: 1.05625-1.09375, bin 138
  // Three rays each: bins 133 and 135 six passes, 137 three; the cell's own points (rays
  // that end in it) cross only cells 0 and 1. At ratio 1.5 bins 133 (3 points, 6 rays),
  // 135 (3, 6) and 137 (3, 3 * 1.5 = 4.5 needed) drop out: the run 128, 130, height 0.3.
  const CoverageGrid carved = build(1.5);
  ASSERT_TRUE(carved.walkable({66, 64}));
  const CoverageGrid plain = build(0);
  EXPECT_FALSE(plain.walkable({66, 64}));
  // No ray passes through the cell it ends in: the wall stays a face.
  EXPECT_FALSE(carved.walkable({68, 64}));
  EXPECT_FALSE(carved.unknown({68, 64}));
}

TEST(SurfaceLayer, RaysToTheFloorStopAboveIt) {
  // The eye at (0, 0, 1); floor points at x = 1 (0.02, bin 128); ten rays to a point
  // beneath the floor at (2, 0, -0.5), own height -0.5. The ray's own height reaches 0.18
  // at t = (1 - 0.18) / (1 + 0.5) = 0.547, x = 1.09: it stops inside cell 1 at height
  // 0.18 (bin 129). Run on, it would cross cell 1 down to -0.125 at x = 1.5 (t 0.75) and
  // carve the floor's bin 128 (3 points, 10 rays).
  const FloorPlane anchor = unitAnchor();
  PolicyConfig config = surfaceConfig();
  config.surface_carving_ratio = 1.0;
  CoverageGrid g(config, anchor, Eigen::Vector3d::UnitX(), 8.0);
  for (int i = 0; i < 3; ++i) g.markSurfacePoint({1, 0, 0.02});
  for (int i = 0; i < 10; ++i) g.markSurfaceRay({0, 0, 1}, {2, 0, -0.5}, -0.5, 0.18);
  ASSERT_TRUE(g.walkable({65, 64}));
  // The floor: the top of bin 128, 0.1; a step from there to a neighbour at 0.1 is fine.
  for (int i = 0; i < 3; ++i) g.markSurfacePoint({1, 1, 0.02});
  EXPECT_TRUE(g.traversable({65, 64}, {65, 65}));
}
