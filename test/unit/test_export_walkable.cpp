// The walkable area: free floor cells kept clear of obstacles, traced into polygons
// with holes, written as JSON and read back with nlohmann::json; and its precision and
// recall against a reachable floor.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "valerant/common/error.h"
#include "valerant/eval/walkable_truth.h"
#include "valerant/map/map_frame.h"
#include "valerant/map/walkable_area.h"

using namespace valerant;

namespace {

// A 1-unit grid of 30 x 30 cells, origin (-15, -15): free floor over cells [5, 25) in
// both axes, one obstacle cell at (15, 15) in the middle, the rest never observed.
FloorGrid floorWithPillar() {
  FloorGrid g;
  g.width = g.height = 30;
  g.resolution = 1;
  g.origin = Eigen::Vector2d(-15, -15);
  g.cells.assign(900, -1);
  for (int row = 5; row < 25; ++row)
    for (int col = 5; col < 25; ++col) g.cells[row * 30 + col] = 0;
  g.cells[15 * 30 + 15] = 100;
  return g;
}

// Map frame = asset scale 1: up z, heading +x, foot at the origin.
MapFrame unitFrame() {
  MapFrame f;
  f.metres_per_unit = 1;
  f.scale_source = "metric slam";
  return f;
}

// Asset (x, z) of floor coordinates (u, v): x = -v, z = -u.
Eigen::Vector2d asset(double u, double v) { return {-v, -u}; }

std::string tempPath(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/valerant_export_walkable";
  std::filesystem::create_directories(dir);
  std::filesystem::remove(dir + "/" + name);
  return dir + "/" + name;
}

}  // namespace

TEST(ExportWalkable, TracesFreeFloorWithAHoleAroundTheObstacle) {
  const WalkableArea area = walkableArea(floorWithPillar(), unitFrame(), {0.0, 0, 0.0});
  ASSERT_EQ(area.polygons.size(), 1u);
  ASSERT_EQ(area.polygons[0].holes.size(), 1u);
  // The outer ring runs through the centres of the border cells: (20 - 1)^2 units; the
  // hole through the centres of the pillar's 4 edge neighbours: a diamond of area 2.
  EXPECT_NEAR(area.areaSquareMetres(), 19.0 * 19.0 - 2.0, 1e-6);
  EXPECT_TRUE(area.contains(asset(-5.5, -5.5)));   // cell (5, 5)'s centre: on the boundary
  EXPECT_TRUE(area.contains(asset(-3, 4)));
  EXPECT_FALSE(area.contains(asset(0.5, 0.5)));    // the pillar
  EXPECT_FALSE(area.contains(asset(12, 0)));       // never observed
}

TEST(ExportWalkable, ClearanceKeepsAwayFromObstacles) {
  // A clearance of 1.2 cells removes every cell whose centre is within 1.2 of the
  // pillar cell's near edge: the 3 x 3 block around it and the 4 cells two away along
  // the axes (1.5 from the edge) stay.
  const WalkableArea area = walkableArea(floorWithPillar(), unitFrame(), {1.2, 0, 0.0});
  ASSERT_EQ(area.polygons.size(), 1u);
  EXPECT_FALSE(area.contains(asset(1.5, 0.5)));  // next to the pillar
  EXPECT_TRUE(area.contains(asset(2.5, 0.5)));   // two cells away
  EXPECT_DOUBLE_EQ(area.clearance_m, 1.2);
}

TEST(ExportWalkable, ClosesSingleCellGapsAndDropsSpeckle) {
  FloorGrid g = floorWithPillar();
  g.cells[10 * 30 + 10] = -1;  // an unobserved cell inside the floor
  g.cells[2 * 30 + 2] = 0;     // a lone free cell far away
  const WalkableArea open = walkableArea(g, unitFrame(), {0.0, 0, 0.0});
  EXPECT_EQ(open.polygons[0].holes.size(), 2u);
  const WalkableArea closed = walkableArea(g, unitFrame(), {0.0, 1, 1.0});
  ASSERT_EQ(closed.polygons.size(), 1u);            // the lone cell (area 0) is gone
  EXPECT_EQ(closed.polygons[0].holes.size(), 1u);   // only the pillar is left
  EXPECT_TRUE(closed.contains(asset(-4.5, -4.5)));  // the closed gap
}

TEST(ExportWalkable, JsonReadsBack) {
  const std::string path = tempPath("walkable.json");
  const WalkableArea area = walkableArea(floorWithPillar(), unitFrame(), {0.0, 0, 0.0});
  writeWalkableJson(path, area, false);
  std::ifstream in(path);
  const nlohmann::json json = nlohmann::json::parse(in);
  EXPECT_NEAR(json["area_m2"].get<double>(), area.areaSquareMetres(), 1e-9);
  EXPECT_EQ(json["polygons"].size(), 1u);
  const WalkableArea back = readWalkableJson(path);
  EXPECT_NEAR(back.areaSquareMetres(), area.areaSquareMetres(), 1e-9);
  EXPECT_EQ(back.polygons[0].outer.size(), area.polygons[0].outer.size());
  EXPECT_THROW(writeWalkableJson(path, area, false), InputError);  // exists: needs --force
}

TEST(ExportWalkable, TruncatedJsonNamesTheFile) {
  const std::string path = tempPath("truncated.json");
  writeWalkableJson(path, walkableArea(floorWithPillar(), unitFrame(), {0.0, 0, 0.0}), false);
  std::filesystem::resize_file(path, std::filesystem::file_size(path) / 2);
  try {
    readWalkableJson(path);
    FAIL() << "a truncated file was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.input(), path);
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos);
  }
  EXPECT_THROW(readWalkableJson(tempPath("missing.json")), InputError);
}

TEST(ExportWalkable, PrecisionAndRecallAgainstReachableFloor) {
  // Reachable floor: 16-unit (0.5 m) cells centred on multiples of 0.5 m around a spawn
  // at the origin, over x in [-10, 9.5] and y in [-10, -0.5] (metres): the half v < 0 of
  // the free floor. The map frame is the world in metres (identity Sim(3)).
  quake3::ReachableFloor reachable;
  reachable.cell_size = 16;
  for (int ix = -20; ix < 20; ++ix)
    for (int iy = -20; iy < 0; ++iy) reachable.cells.emplace_back(ix * 16.f, iy * 16.f, 0.f);
  const FloorGrid grid = floorWithPillar();
  const WalkableArea area = walkableArea(grid, unitFrame(), {0.0, 0, 0.0});
  const WalkableTruth t =
      evaluateWalkableTruth(area, grid, unitFrame(), Sim3{}, reachable, Eigen::Vector3f(0, 0, 24));
  EXPECT_EQ(t.walkable_cells, 20 * 20 - 1);  // every free cell but the pillar
  EXPECT_NEAR(t.precision, 200.0 / 399.0, 1e-9);  // rows v < 0: 10 of 20
  EXPECT_EQ(t.reachable_cells, 800);
  EXPECT_EQ(t.reachable_cells_explored, 800);  // all fall in observed grid cells
  // The outer ring runs through the border cells' centres (u, v = +-9.5): reachable
  // cells at x = -10 (20) or y = -10 (40), one in both, fall outside it.
  EXPECT_NEAR(t.recall_explored, (800.0 - 59.0) / 800.0, 1e-9);
  EXPECT_DOUBLE_EQ(t.recall_all, t.recall_explored);
}

TEST(ExportFrame, JsonRoundTripAndBadInput) {
  MapFrame f;
  f.foot = Eigen::Vector3d(1, 2, 3);
  f.up = Eigen::Vector3d(0, 0, 1);
  f.forward = Eigen::Vector3d(0, 1, 0);
  f.eye_height = 0.25;
  f.metres_per_unit = 6.25;
  f.scale_source = "eye height";
  const MapFrame back = mapFrameFromJson(toJson(f), "report.json");
  EXPECT_TRUE(back.mapToAsset().isApprox(f.mapToAsset()));
  EXPECT_EQ(back.scale_source, "eye height");
  nlohmann::json bad = toJson(f);
  bad.erase("up");
  EXPECT_THROW(mapFrameFromJson(bad, "report.json"), InputError);
  bad = toJson(f);
  bad["forward"] = {0, 0, 1};  // not level
  EXPECT_THROW(mapFrameFromJson(bad, "report.json"), InputError);
}
