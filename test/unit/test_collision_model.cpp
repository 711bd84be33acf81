#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "valerant/world/quake3/collision_model.h"
#include "valerant/world/quake3/pk3_archive.h"
#include "valerant/world/quake3/player_hull.h"
#include "valerant/world/quake3/reachable_floor.h"

#include "brush_world.h"
#include "openarena_data.h"

namespace valerant::quake3 {
namespace {

using Eigen::Vector3f;
using test::boxBrush;

// Floor slab with its top at z = 0 plus a 16-unit step at x >= 64.
CollisionModel floorWithStep() {
  return CollisionModel({boxBrush({-512, -512, -16}, {512, 512, 0}),
                         boxBrush({64, -512, 0}, {512, 512, 16})});
}

const PlayerHull kHull;

TEST(CollisionModel, PointsInsideAndOnTheSurface) {
  const CollisionModel m = floorWithStep();
  EXPECT_TRUE(m.pointInSolid({0, 0, -8}));
  EXPECT_TRUE(m.pointInSolid({100, 0, 8}));
  EXPECT_FALSE(m.pointInSolid({0, 0, 1}));
  EXPECT_FALSE(m.pointInSolid({0, 0, 0}));  // on the surface: touching, not inside
  EXPECT_FALSE(m.pointInSolid({0, 0, -10000}));
  EXPECT_FALSE(m.pointInSolid({2000, 0, -8}));
}

TEST(CollisionModel, BoxRestingOnTheFloorIsNotInSolid) {
  const CollisionModel m = floorWithStep();
  EXPECT_FALSE(m.boxInSolid({0, 0, 24}, kHull.mins, kHull.maxs));
  EXPECT_TRUE(m.boxInSolid({0, 0, 23}, kHull.mins, kHull.maxs));
  // Touching the riser of the step from the side is not solid; one unit further is.
  EXPECT_FALSE(m.boxInSolid({49, 0, 24}, kHull.mins, kHull.maxs));
  EXPECT_TRUE(m.boxInSolid({50, 0, 24}, kHull.mins, kHull.maxs));
}

TEST(CollisionModel, BoundsComeFromTheBrushes) {
  const CollisionModel m = floorWithStep();
  EXPECT_EQ(m.brushes().size(), 2u);
  EXPECT_TRUE(m.bounds().min().isApprox(Vector3f(-512, -512, -16)));
  EXPECT_TRUE(m.bounds().max().isApprox(Vector3f(512, 512, 16)));
}

TEST(CollisionModel, DropOntoFloorAndStep) {
  const CollisionModel m = floorWithStep();
  auto z = m.dropBox({0, 0, 100}, kHull.mins, kHull.maxs, 1000);
  ASSERT_TRUE(z);
  EXPECT_NEAR(*z, 24, 1e-3);
  // Overhanging the step edge, the box rests on the step.
  z = m.dropBox({60, 0, 100}, kHull.mins, kHull.maxs, 1000);
  ASSERT_TRUE(z);
  EXPECT_NEAR(*z, 40, 1e-3);
  // Already resting: stays where it is.
  z = m.dropBox({0, 0, 24}, kHull.mins, kHull.maxs, 1000);
  ASSERT_TRUE(z);
  EXPECT_NEAR(*z, 24, 1e-3);
  EXPECT_FALSE(m.boxInSolid({60, 0, *m.dropBox({60, 0, 100}, kHull.mins, kHull.maxs, 1000)},
                            kHull.mins, kHull.maxs));
}

TEST(CollisionModel, DropMissesReturnNothing) {
  const CollisionModel m = floorWithStep();
  EXPECT_FALSE(m.dropBox({2000, 0, 100}, kHull.mins, kHull.maxs, 1000));  // nothing below
  EXPECT_FALSE(m.dropBox({0, 0, 100}, kHull.mins, kHull.maxs, 50));       // out of range
  EXPECT_FALSE(m.dropBox({0, 0, 0}, kHull.mins, kHull.maxs, 1000));       // starts in solid
  EXPECT_FALSE(m.dropBox({0, 0, -100}, kHull.mins, kHull.maxs, 1000));    // below the floor
}

TEST(CollisionModel, DropSlidesPastAWallItTouches) {
  // A wall at x >= 15 touches the side of a box centred at x = 0 all the way down.
  const CollisionModel m({boxBrush({-512, -512, -16}, {512, 512, 0}),
                          boxBrush({15, -512, 0}, {31, 512, 512})});
  auto z = m.dropBox({0, 0, 300}, kHull.mins, kHull.maxs, 1000);
  ASSERT_TRUE(z);
  EXPECT_NEAR(*z, 24, 1e-3);
}

TEST(CollisionModel, SlopedBrushGetsBoundsAndCatchesTheBoxCorner) {
  // Ramp under the plane z = x, for -64 <= x, y <= 64 and z >= -64; it has no
  // axial top side, so its bounds come from clipping the planes.
  const float s = std::sqrt(0.5f);
  ConvexBrush ramp;
  ramp.contents = kContentsSolid;
  ramp.planes = {{-s, 0, s, 0}, {0, 0, -1, 64}, {1, 0, 0, 64}, {-1, 0, 0, 64},
                 {0, 1, 0, 64}, {0, -1, 0, 64}};
  const CollisionModel m({ramp});
  EXPECT_NEAR(m.bounds().max().z(), 64, 1e-3);
  EXPECT_NEAR(m.bounds().min().z(), -64, 1e-3);
  EXPECT_TRUE(m.pointInSolid({10, 0, 9}));
  EXPECT_FALSE(m.pointInSolid({10, 0, 11}));
  // The box's high-x bottom edge meets the ramp first: at z = x + 15.
  auto z = m.dropBox({0, 0, 200}, kHull.mins, kHull.maxs, 1000);
  ASSERT_TRUE(z);
  EXPECT_NEAR(*z, 15 + 24, 1e-2);
}

// A map whose world model is one 3x3-control-point patch over [-64, 64]^2 at z = 0,
// with its middle row raised to `bump` (the surface peaks at bump / 2 along y = 0).
BspMap patchMap(float bump, int contents, int surface_flags = 0) {
  BspMap map;
  map.shaders.push_back({"textures/test/patch", surface_flags, contents});
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      BspVertex v;
      v.position = {-64.f + 64 * c, -64.f + 64 * r, r == 1 ? bump : 0.f};
      v.texcoord = v.lmcoord = Eigen::Vector2f::Zero();
      v.normal = Vector3f::UnitZ();
      map.vertices.push_back(v);
    }
  BspFace face;
  face.type = BspFaceType::kPatch;
  face.num_vertices = 9;
  face.patch_size = {3, 3};
  face.normal = Vector3f::UnitZ();
  map.faces.push_back(face);
  BspModel world;
  world.num_faces = 1;
  world.mins = Vector3f(-64, -64, 0);
  world.maxs = Vector3f(64, 64, 32);
  map.models.push_back(world);
  return map;
}

TEST(CollisionModel, PatchesCollide) {
  const CollisionModel flat = CollisionModel::fromBsp(patchMap(0, kContentsSolid));
  ASSERT_FALSE(flat.brushes().empty());
  auto z = flat.dropBox({10, -20, 100}, kHull.mins, kHull.maxs, 1000);
  ASSERT_TRUE(z);
  EXPECT_NEAR(*z, 24, 1e-3);
  EXPECT_FALSE(flat.boxInSolid({10, -20, 24}, kHull.mins, kHull.maxs));
  EXPECT_TRUE(flat.boxInSolid({10, -20, 20}, kHull.mins, kHull.maxs));  // straddles the sheet

  const CollisionModel bump = CollisionModel::fromBsp(patchMap(32, kContentsSolid));
  z = bump.dropBox({0, 0, 100}, kHull.mins, kHull.maxs, 1000);
  ASSERT_TRUE(z);
  EXPECT_NEAR(*z, 16 + 24, 1e-2);
}

TEST(CollisionModel, NonSolidPatchesAreIgnored) {
  EXPECT_TRUE(CollisionModel::fromBsp(patchMap(0, 0)).brushes().empty());
  EXPECT_TRUE(CollisionModel::fromBsp(patchMap(0, kContentsSolid, kSurfNonSolid)).brushes().empty());
  EXPECT_FALSE(CollisionModel::fromBsp(patchMap(0, kContentsPlayerClip)).brushes().empty());
}

// ------------------------------------------------------------------ real map
class CollisionModelOnMap : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!test::openArenaInstalled()) return;
    Pk3FileSystem fs;
    fs.mountDirectory(Pk3FileSystem::defaultDataDir());
    auto bytes = fs.read("maps/oa_dm1.bsp");
    ASSERT_TRUE(bytes);
    map_ = std::make_unique<BspMap>(parseBsp(*bytes, "oa_dm1"));
    model_ = std::make_unique<CollisionModel>(CollisionModel::fromBsp(*map_));
  }
  static void TearDownTestSuite() {
    model_.reset();
    map_.reset();
  }
  void SetUp() override { VALERANT_REQUIRE_OPENARENA(); }
  inline static std::unique_ptr<BspMap> map_;
  inline static std::unique_ptr<CollisionModel> model_;
};

TEST_F(CollisionModelOnMap, HasBrushesAndFreeSpawns) {
  EXPECT_GT(model_->brushes().size(), 100u);
  const auto spawns = map_->spawnPoints();
  ASSERT_FALSE(spawns.empty());
  for (const auto& s : spawns) {
    // The game puts the player 9 units above the spawn point: oa_dm1 has a spawn
    // whose hull would dip 0.8 units into a player-clip brush at the point itself.
    const Vector3f origin = s.origin + Vector3f(0, 0, 9);
    EXPECT_FALSE(model_->boxInSolid(origin, kHull.mins, kHull.maxs)) << s.origin.transpose();
    // ... and it falls onto a floor close below.
    auto z = model_->dropBox(origin, kHull.mins, kHull.maxs, 256);
    ASSERT_TRUE(z) << s.origin.transpose();
    EXPECT_GE(*z, s.origin.z() - 64);
  }
  const Vector3f below = model_->bounds().center() - Vector3f(0, 0, 10000);
  EXPECT_FALSE(model_->pointInSolid(below));
  EXPECT_FALSE(model_->boxInSolid(below, kHull.mins, kHull.maxs));
}

TEST_F(CollisionModelOnMap, BoxInsideAWallIsSolid) {
  // A wall: an axial block brush, tall and at least 8 units thick.
  int walls = 0;
  for (const auto& b : model_->brushes()) {
    const Vector3f size = b.bounds.sizes();
    if (b.planes.size() != 6 || size.z() < 64 || size.head<2>().minCoeff() < 8) continue;
    ++walls;
    EXPECT_TRUE(model_->boxInSolid(b.bounds.center(), Vector3f::Constant(-2), Vector3f::Constant(2)));
  }
  EXPECT_GT(walls, 0);
}

// The playable world holds every spawn and every hull centre (28 above the feet) of
// the floor walkable from the first spawn, so in-world poses never count as
// penetrations; 16 units past the world model's bounds is outside, as is a point far
// below the map.
TEST_F(CollisionModelOnMap, WalkableFloorIsInsideThePlayableWorld) {
  ASSERT_TRUE(model_->playableWorld().has_value());
  const Vector3f centre_above_feet(0, 0, 28);
  for (const auto& s : map_->spawnPoints()) EXPECT_FALSE(model_->pointOutsideWorld(s.origin)) << s.origin.transpose();
  const ReachableFloor floor = floodFillReachableFloor(*model_, map_->spawnPoints().front().origin);
  ASSERT_GT(floor.cells.size(), 1000u);
  int outside = 0;
  for (const auto& c : floor.cells) outside += model_->pointOutsideWorld(c + centre_above_feet);
  EXPECT_EQ(outside, 0) << "of " << floor.cells.size() << " walkable cells";
  const BspModel& world = map_->models[0];
  const Vector3f spawn = map_->spawnPoints().front().origin;
  EXPECT_TRUE(model_->pointOutsideWorld({world.mins.x() - 16, spawn.y(), spawn.z()}));
  EXPECT_TRUE(model_->pointOutsideWorld({world.maxs.x() + 16, spawn.y(), spawn.z()}));
  EXPECT_TRUE(model_->pointOutsideWorld(model_->bounds().center() - Vector3f(0, 0, 10000)));
}

}  // namespace
}  // namespace valerant::quake3
