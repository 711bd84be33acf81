// A branch that starts without a floor (uninitialised SLAM): BranchCheck must not read
// heights from the estimator's placeholder floor. Map frame = the first camera's
// optical frame (y down); the true floor is the plane y = 0.5, so the camera height
// is 0.5 while the placeholder relation says 1.0.
#include <gtest/gtest.h>

#include "valerant/explore/branch_check.h"
#include "walking_branch.h"

using namespace valerant;
using valerant::test::trackedAtZ;

namespace {

constexpr double kHeight = 0.5;

// What FloorEstimator::at gives before any floor: distance 1 along -y, unknown.
FloorPlane placeholder(const Eigen::Vector3d& c) {
  FloorPlane p;
  p.c = c;
  p.n = {0, -1, 0};
  p.q = c - p.n;
  p.known = false;
  return p;
}

FloorPlane trueFloor(const Eigen::Vector3d& c) { return valerant::test::floorBelow(c, kHeight); }

// 400 confident floor points (y = 0.5) within 0.05 of the body axis at z: the
// placeholder puts them at h = 0.5, inside the body band, and 400 >= 300 would be a
// deep penetration; on the true floor they have h = 0.
KeyframeCloud floorPatch(double z) {
  KeyframeCloud cloud;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j)
      cloud.points.push_back({Eigen::Vector3f(-0.05f + 0.005f * i, kHeight, z - 0.05f + 0.005f * j), {}, 10.f});
  return cloud;
}

}  // namespace

TEST(FloorBackfill, FramesBeforeTheFirstFloorTakeItsRelation) {
  BranchCheck check{Config(), {}};
  const KeyframeCloud patch = floorPatch(0.2);
  for (int i = 0; i < 10; ++i) {
    const TrackedFrame f = trackedAtZ(0.1 * i);
    const Eigen::Vector3d c = f.camera_to_map.translation();
    check.add(f, i == 2 ? &patch : nullptr, i < 5 ? placeholder(c) : trueFloor(c));
  }
  const std::vector<FloorPlane> floors = check.floors();
  ASSERT_EQ(floors.size(), 10u);
  for (int i = 0; i < 5; ++i) {
    EXPECT_TRUE(floors[i].known);
    EXPECT_NEAR(floors[i].cameraHeight(), kHeight, 1e-12);
    EXPECT_NEAR(floors[i].normalisedHeight({0, kHeight, 0.1 * i}), 0.0, 1e-12);
  }
  const BranchVerdict v = check.finish("uw", false);
  EXPECT_FALSE(v.floor_unknown);
  EXPECT_FALSE(v.collision_pc);
  EXPECT_EQ(v.occupied_max, 0);
}

TEST(FloorBackfill, TranslationWithoutAnyFloorIsUnknownRotationIsNot) {
  BranchCheck check{Config(), {}};
  const KeyframeCloud patch = floorPatch(0.2);
  for (int i = 0; i < 10; ++i) {
    const TrackedFrame f = trackedAtZ(0.1 * i);
    check.add(f, i == 2 ? &patch : nullptr, placeholder(f.camera_to_map.translation()));
  }
  EXPECT_FALSE(check.floors().front().known);
  const BranchVerdict walk = check.finish("uw", false);
  EXPECT_TRUE(walk.floor_unknown);
  EXPECT_FALSE(walk.collision_pc);  // not judged on the placeholder (it would say 400)
  EXPECT_FALSE(check.finish("jq", true).floor_unknown);
}
