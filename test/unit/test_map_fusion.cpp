// Map fusion and its files: voxel filtering, rewind truncation, the floor grid,
// read-back of every export with the library that reads it in the wild, and the live
// mirror (live_map.h): extended keyframe by keyframe it gives what MapFusion rebuilds,
// and a rewind drops the dropped geometry.
#include <gtest/gtest.h>
#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "valerant/common/error.h"
#include "valerant/map/map_exports.h"
#include "valerant/map/live_map.h"
#include "valerant/map/map_fusion.h"

using namespace valerant;

namespace {

// A keyframe at (0, 0, 1) looking along +X over a floor z = 0 (x in [1, 3), |y| < 1)
// and a wall at x = 3 (z in [0, 2)), points every 0.1.
KeyframeCloud room() {
  KeyframeCloud kf;
  kf.camera_to_map = Eigen::Isometry3d::Identity();
  kf.camera_to_map.translation() = Eigen::Vector3d(0, 0, 1);
  auto add = [&](float x, float y, float z, float confidence) {
    CloudPoint p;
    p.position = {x, y, z};
    p.rgb = {200, 100, 50};
    p.confidence = confidence;
    kf.points.push_back(p);
  };
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) add(1 + 0.1f * i, -1 + 0.1f * j, 0, 10);
  for (int j = 0; j < 20; ++j)
    for (int k = 0; k < 20; ++k) add(3, -1 + 0.1f * j, 0.1f * k, 10);
  add(2, 0, 0.5f, 1);  // below the confidence cut: never fused
  return kf;
}

FloorPlane flatFloor() {
  FloorPlane f;
  f.q = {0, 0, 0};
  f.n = {0, 0, 1};
  f.c = {0, 0, 1};
  return f;
}

std::string tempDir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/valerant_" + name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}


// 10 x 10 floor points every 0.1 over x in [x0, x0 + 1), y in [0, 1), z = 0 (h = 0 under
// a camera 1 above), each in the middle of its 0.1 square so none lies on a voxel border,
// and one point 0.5 above the floor: an obstacle (h in [0.18, 1.19]).
std::shared_ptr<const FusedKeyframe> strip(float x0) {
  auto kf = std::make_shared<FusedKeyframe>();
  kf->id = newKeyframeId();
  kf->camera_to_map = Eigen::Isometry3d::Identity();
  kf->camera_to_map.translation() = Eigen::Vector3d(x0 - 1, 0, 1);
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) kf->points.push_back({{x0 + 0.05f + 0.1f * i, 0.05f + 0.1f * j, 0}, {10, 20, 30}, 5, 0});
  kf->points.push_back({{x0 + 0.05f, 0.05f, 0.5f}, {200, 0, 0}, 5, 0.5f});
  return kf;
}

struct LiveMapSetup {
  MapConfig map;
  CollisionConfig collision;
  PolicyConfig policy;
  LiveMapSetup() {
    map.voxel_eye_heights = 0.2;  // kappa = 1: voxels of 0.2
    map.octree_eye_heights = 0.2;
    map.max_range_eye_heights = 10;
    map.grid_cell_fraction = 0.5;
    policy.grid_cells = 16;  // 16 cells of 1 unit; floor grid cells of 0.5
  }
  CoverageGrid grid() const { return CoverageGrid(policy, flatFloor(), Eigen::Vector3d::UnitX(), 8.0); }
};

size_t occupiedLeaves(const octomap::ColorOcTree& tree) {
  size_t n = 0;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) n += tree.isNodeOccupied(*it);
  return n;
}

void expectSameProducts(const LiveMap& live, const MapFusion& rebuilt, const LiveMapSetup& f) {
  const auto a = live.voxelCloud(), b = rebuilt.voxelCloud(0.2);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].position, b[i].position);
    EXPECT_EQ(a[i].h, b[i].h);
  }
  EXPECT_EQ(live.floorGrid().cells, rebuilt.floorGrid(f.grid(), 0.5).cells);
  EXPECT_EQ(occupiedLeaves(live.octree()), occupiedLeaves(*rebuilt.octree(0.2)));
}

}  // namespace

TEST(MapFusion, FusesConfidentPointsWithHeightsAndTruncates) {
  MapFusion map(MapConfig{}, CollisionConfig{});
  map.fuse(room(), flatFloor());
  EXPECT_EQ(map.pointCount(), 800u);
  const size_t marker = map.marker();
  map.fuse(room(), flatFloor());
  EXPECT_EQ(map.pointCount(), 1600u);
  map.truncate(marker);  // a rewind drops what came after the marker
  EXPECT_EQ(map.pointCount(), 800u);
  // Wall points at z = 0.5 have h = 0.5; floor points h = 0.
  for (const auto& p : map.keyframes()[0]->points) EXPECT_FLOAT_EQ(p.h, p.position.z());
  // Duplicated points collapse in the voxel grid: 0.2-sized voxels hold 2 x 2 floor
  // points (400 / 4 = 100) and 2 x 2 wall points (400 / 4 = 100).
  map.fuse(room(), flatFloor());
  EXPECT_EQ(map.voxelCloud(0.2).size(), 200u);
}

TEST(MapFusion, FloorGridMarksFloorAndObstacles) {
  MapFusion map(MapConfig{}, CollisionConfig{});
  map.fuse(room(), flatFloor());
  PolicyConfig policy;
  policy.grid_cells = 16;  // 16 cells of 1 unit: extent [-8, 8)
  const CoverageGrid grid(policy, flatFloor(), Eigen::Vector3d::UnitX(), 8.0);
  const FloorGrid g = map.floorGrid(grid, 0.5);
  ASSERT_EQ(g.width, 32);
  EXPECT_DOUBLE_EQ(g.origin.x(), -8.0);
  auto at = [&](double u, double v) {
    return g.cells[static_cast<size_t>((v + 8) / 0.5) * g.width + static_cast<size_t>((u + 8) / 0.5)];
  };
  EXPECT_EQ(at(2.0, 0.0), 0);     // floor
  EXPECT_EQ(at(3.1, 0.0), 100);   // the wall (h in the body band)
  EXPECT_EQ(at(-4.0, 0.0), -1);   // never seen
}

TEST(MapExports, EveryFormatReadsBack) {
  const std::string dir = tempDir("exports");
  MapFusion map(MapConfig{}, CollisionConfig{});
  map.fuse(room(), flatFloor());
  const auto cloud = map.voxelCloud(0.05);
  ASSERT_EQ(cloud.size(), 800u);

  writeCloudPly(dir + "/map.ply", cloud, false);
  pcl::PointCloud<pcl::PointXYZRGB> ply;
  ASSERT_EQ(pcl::io::loadPLYFile(dir + "/map.ply", ply), 0);
  ASSERT_EQ(ply.size(), 800u);
  EXPECT_EQ(ply[0].r, 200);
  EXPECT_EQ(ply[0].g, 100);

  writeCloudPcd(dir + "/map.pcd", cloud, false);
  pcl::PCLPointCloud2 pcd;
  ASSERT_EQ(pcl::io::loadPCDFile(dir + "/map.pcd", pcd), 0);
  EXPECT_EQ(pcd.width * pcd.height, 800u);
  bool has_confidence = false;
  for (const auto& f : pcd.fields) has_confidence |= f.name == "confidence";
  EXPECT_TRUE(has_confidence);

  auto tree = map.octree(0.1);
  writeOctreeBt(dir + "/map.bt", *tree, false);
  octomap::OcTree tree_read(0.1);
  ASSERT_TRUE(tree_read.readBinary(dir + "/map.bt"));
  const auto* wall = tree_read.search(3.0, 0.05, 1.05);
  ASSERT_NE(wall, nullptr);
  EXPECT_TRUE(tree_read.isNodeOccupied(wall));
  const auto* free_space = tree_read.search(1.5, 0.05, 0.55);  // on the ray to the wall
  ASSERT_NE(free_space, nullptr);
  EXPECT_FALSE(tree_read.isNodeOccupied(free_space));

  PolicyConfig policy;
  policy.grid_cells = 16;
  const CoverageGrid grid(policy, flatFloor(), Eigen::Vector3d::UnitX(), 8.0);
  writeFloorGrid(dir + "/grid", map.floorGrid(grid, 0.5), false);
  const cv::Mat image = cv::imread(dir + "/grid.pgm", cv::IMREAD_UNCHANGED);
  ASSERT_EQ(image.cols, 32);
  const YAML::Node yaml = YAML::LoadFile(dir + "/grid.yaml");
  EXPECT_EQ(yaml["image"].as<std::string>(), "grid.pgm");
  EXPECT_DOUBLE_EQ(yaml["resolution"].as<double>(), 0.5);
  EXPECT_DOUBLE_EQ(yaml["origin"][0].as<double>(), -8.0);
  // Cell (u = 2, v = 0) is floor: image row = height - 1 - row.
  EXPECT_EQ(image.at<uint8_t>(31 - 16, 20), 254);
  EXPECT_EQ(image.at<uint8_t>(31 - 16, 22), 0);  // u = 3.0: the wall
}

TEST(MapExports, NeverOverwritesWithoutForce) {
  const std::string dir = tempDir("overwrite");
  MapFusion map(MapConfig{}, CollisionConfig{});
  map.fuse(room(), flatFloor());
  const auto cloud = map.voxelCloud(0.05);
  writeCloudPly(dir + "/map.ply", cloud, false);
  const auto before = std::filesystem::file_size(dir + "/map.ply");
  EXPECT_THROW(writeCloudPly(dir + "/map.ply", std::vector<FusedPoint>(cloud.begin(), cloud.begin() + 10), false),
               InputError);
  EXPECT_EQ(std::filesystem::file_size(dir + "/map.ply"), before);
  EXPECT_NO_THROW(writeCloudPly(dir + "/map.ply", cloud, true));
  EXPECT_THROW(writeCloudPly(dir + "/missing/map.ply", cloud, false), InputError);
}

TEST(MapFusion, VoxelCloudAveragesAndSurvivesFarPoints) {
  // Two points in voxel [0, 1)^3 and one a million voxels away along each axis: a
  // bounding box of 10^18 leaves, far past PCL VoxelGrid's 32-bit voxel indices.
  KeyframeCloud kf;
  auto add = [&](Eigen::Vector3f x, uint8_t red, float confidence) {
    CloudPoint p;
    p.position = x;
    p.rgb = {red, 0, 0};
    p.confidence = confidence;
    kf.points.push_back(p);
  };
  add({0.2f, 0.2f, 0.2f}, 100, 5);
  add({0.6f, 0.4f, 0.8f}, 200, 7);
  add({1e6f, 1e6f, 1e6f}, 50, 9);
  MapFusion map(MapConfig{}, CollisionConfig{});
  map.fuse(kf, flatFloor());
  const auto cloud = map.voxelCloud(1.0);
  ASSERT_EQ(cloud.size(), 2u);
  // First voxel: centroid (0.4, 0.3, 0.5), red (100 + 200) / 2 = 150, confidence 6,
  // h = mean height over the floor z = 0 with the camera 1 above = 0.5.
  EXPECT_TRUE(cloud[0].position.isApprox(Eigen::Vector3f(0.4f, 0.3f, 0.5f), 1e-6f));
  EXPECT_EQ(cloud[0].rgb[0], 150);
  EXPECT_FLOAT_EQ(cloud[0].confidence, 6.0f);
  EXPECT_FLOAT_EQ(cloud[0].h, 0.5f);
  EXPECT_FLOAT_EQ(cloud[1].position.x(), 1e6f);
}

TEST(LiveMap, ExtendsLikeARebuildAndRewindsCleanly) {
  const LiveMapSetup f;
  LiveMap live(f.map, f.collision, f.grid(), 1.0);
  MapFusion rebuilt(f.map, f.collision);
  std::vector<std::shared_ptr<const FusedKeyframe>> episode{strip(1.0f)};
  rebuilt.add(episode[0]);
  EXPECT_EQ(live.update(episode), 1u);
  // The strip covers 5 x 5 voxels of 0.2 on the floor; the obstacle's voxel (z in
  // [0.4, 0.6)) makes 26.
  EXPECT_EQ(live.voxelCloud().size(), 26u);
  expectSameProducts(live, rebuilt, f);

  // The next step adds a strip on x in [2, 3): only it is inserted.
  episode.push_back(strip(2.0f));
  rebuilt.add(episode[1]);
  EXPECT_EQ(live.update(episode), 1u);
  EXPECT_EQ(live.voxelCloud().size(), 52u);
  expectSameProducts(live, rebuilt, f);
  // Nothing new: nothing inserted.
  EXPECT_EQ(live.update(episode), 0u);

  // A rewind drops the second strip and commits a third on x in [4, 5): the mirror is
  // rebuilt from the first and third, and the second strip's floor cells are unknown again.
  // Floor grid: 32 x 32 cells of 0.5 from (-8, -8); (u, v) = (2.5, 0.5) is row 17, column 21.
  const size_t x25 = 17 * 32 + 21;
  EXPECT_EQ(live.floorGrid().cells[x25], 0);  // seen floor
  episode[1] = strip(4.0f);
  rebuilt.truncate(1);
  rebuilt.add(episode[1]);
  EXPECT_EQ(live.update(episode), 2u);
  EXPECT_EQ(live.floorGrid().cells[x25], -1);
  EXPECT_EQ(live.voxelCloud().size(), 52u);
  expectSameProducts(live, rebuilt, f);
}

TEST(LiveMap, KeyframesWithoutPointsLeaveAnEmptyMap) {
  // map_fusion's first update at 160 x 120 carries keyframes whose clouds are empty;
  // OctoMap's ColorOcTree crashed updating the inner nodes of a tree with no root.
  const LiveMapSetup f;
  LiveMap live(f.map, f.collision, f.grid(), 1.0);
  auto empty = std::make_shared<FusedKeyframe>();
  empty->id = newKeyframeId();
  empty->camera_to_map = Eigen::Isometry3d::Identity();
  std::vector<std::shared_ptr<const FusedKeyframe>> episode{empty};
  EXPECT_EQ(live.update(episode), 1u);
  EXPECT_EQ(live.octree().size(), 0u);
  EXPECT_TRUE(live.voxelCloud().empty());
  MapFusion rebuilt(f.map, f.collision);
  rebuilt.add(empty);
  EXPECT_EQ(rebuilt.octree(0.2)->size(), 0u);
  // Points arriving later still go in.
  episode.push_back(strip(1.0f));
  EXPECT_EQ(live.update(episode), 1u);
  EXPECT_GT(occupiedLeaves(live.octree()), 0u);
}

TEST(LiveMap, KeyframeIdsAreNeverReused) {
  const uint64_t a = newKeyframeId(), b = newKeyframeId();
  EXPECT_NE(a, b);
  EXPECT_EQ(a >> 32, b >> 32);  // the same process
}
