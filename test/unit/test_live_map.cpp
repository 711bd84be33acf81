// The live map mirror (live_map.h): extending its products keyframe by keyframe gives
// what MapFusion rebuilds from scratch, and a rewind drops the dropped geometry.
#include <gtest/gtest.h>
#include <octomap/ColorOcTree.h>

#include "valerant/map/live_map.h"

using namespace valerant;

namespace {

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

FloorPlane flatFloor() {
  FloorPlane f;
  f.q = {0, 0, 0};
  f.n = {0, 0, 1};
  f.c = {0, 0, 1};
  return f;
}

struct Fixture {
  MapConfig map;
  CollisionConfig collision;
  PolicyConfig policy;
  Fixture() {
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

void expectSameProducts(const LiveMap& live, const MapFusion& rebuilt, const Fixture& f) {
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

TEST(LiveMap, ExtendsLikeARebuildAndRewindsCleanly) {
  const Fixture f;
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

TEST(LiveMap, KeyframeIdsAreNeverReused) {
  const uint64_t a = newKeyframeId(), b = newKeyframeId();
  EXPECT_NE(a, b);
  EXPECT_EQ(a >> 32, b >> 32);  // the same process
}
