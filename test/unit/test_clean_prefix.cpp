// Clean prefixes of rejected translations (clean_prefix.h): how many leading frames stop
// a margin short of the first unsafe frame, on hand-worked straight walks.
#include <gtest/gtest.h>

#include "valerant/explore/branch_check.h"
#include "valerant/explore/clean_prefix.h"
#include "walking_branch.h"

using namespace valerant;
using valerant::test::trackedAtZ;

namespace {

// 16 frames walking +x on the floor z = 0, camera at height `kappa`: x = 0.25, 0.5 .. 4.0
// (exact binary fractions, so the distances below compare exactly).
std::vector<FloorPlane> straightWalk(double kappa) {
  std::vector<FloorPlane> frames;
  for (int i = 0; i < 16; ++i) {
    FloorPlane p;
    p.c = {0.25 * (i + 1), 0, kappa};
    p.q = {p.c.x(), 0, 0};
    p.n = Eigen::Vector3d::UnitZ();
    frames.push_back(p);
  }
  return frames;
}

}  // namespace

// Nothing fired: the whole rollout is clean.
TEST(CleanPrefix, NothingFiredKeepsEveryFrame) { EXPECT_EQ(cleanPrefixFrames(straightWalk(1), -1, -1, 1, 1), 16); }

// Unsafe from frame 12 (x = 3.25), kappa 1, margin 1: the last kept camera must be at
// x <= 2.25, frame 8, so 9 frames; it advanced 2.0 >= 1 from frame 0 (x = 0.25).
TEST(CleanPrefix, StopsOneMarginShortOfTheFirstUnsafeFrame) {
  EXPECT_EQ(cleanPrefixFrames(straightWalk(1), 12, 12, 1, 1), 9);
  // Margin 0.5: x <= 2.75, frame 10, 11 frames.
  EXPECT_EQ(cleanPrefixFrames(straightWalk(1), 12, 12, 0.5, 1), 11);
}

// Both lengths scale with kappa: at kappa 2 the margin is 2 (x <= 1.25, frame 4) but
// the advance must be 2 (x >= 2.25): no prefix is worth offering.
TEST(CleanPrefix, TooShortAPrefixIsNotOffered) {
  EXPECT_EQ(cleanPrefixFrames(straightWalk(2), 12, 12, 1, 1), 0);
  EXPECT_EQ(cleanPrefixFrames(straightWalk(2), 12, 12, 1, 0.5), 5);
}

// The SLAM lost track at frame 12: the obstacle is measured from frame 11 (x = 3.0),
// so x <= 2.0, frame 7, 8 frames. Lost at frame 0: nothing tracked, no prefix.
TEST(CleanPrefix, ALostFrameIsMeasuredFromTheLastTrackedOne) {
  EXPECT_EQ(cleanPrefixFrames(straightWalk(1), 12, 11, 1, 1), 8);
  EXPECT_EQ(cleanPrefixFrames(straightWalk(1), 0, -1, 1, 1), 0);
}

// Height differences do not count: the margin is measured across the floor normal.
TEST(CleanPrefix, MarginIsHorizontal) {
  std::vector<FloorPlane> frames = straightWalk(1);
  for (auto& f : frames) f.c.z() += f.c.x();  // a ramp: the camera climbs as it walks
  for (auto& f : frames) f.q.z() = f.c.z() - 1;
  EXPECT_EQ(cleanPrefixFrames(frames, 12, 12, 1, 1), 9);
}

// The wiring in BranchCheck, on the walk of test_committed_points.cpp: kappa 0.5,
// camera at z = 0, 0.1 .. 0.9, a wall at x = 0.08 from z = 0.3 on, known only from the
// previous step. The sample at z = 0.3 holds 28 points, z = 0.4 and z = 0.5 hold 52, so
// the run that fires starts at frame 4 (z = 0.4). Margin 0.5 (0.25 units): the last
// kept camera is at z <= 0.15, frame 1, so 2 frames; it advanced 0.1 from frame 0, over
// the 0.05 units of min_advance 0.1.
namespace {

CommittedSteps wallFromZ03() {
  KeyframeCloud wall;
  for (int i = 30; i <= 90; ++i)
    for (double y : {0.05, 0.15, 0.25, 0.35})
      wall.points.push_back({Eigen::Vector3f(0.08f, static_cast<float>(y), 0.01f * i), {}, 10.f});
  CommittedPoints committed(Config().collision);
  committed.add({wall}, {valerant::test::floorBelow(Eigen::Vector3d::Zero(), 0.5)});
  return committed.points();
}

// The walk of test_committed_points.cpp (z = 0 .. 0.9, kappa 0.5) beside `wall`,
// the SLAM lost from frame `lost_from` on.
BranchVerdict walkBeside(const Config& config, CommittedSteps wall,
                         bool rotation_only, int lost_from = 10) {
  BranchCheck check(config, std::move(wall));
  for (int i = 0; i < 10; ++i) {
    TrackedFrame f = trackedAtZ(0.1 * i);
    if (i >= lost_from) f.state = TrackingState::kLost;
    check.add(f, nullptr, valerant::test::floorBelow(f.camera_to_map.translation(), 0.5));
  }
  return check.finish(rotation_only ? "jq" : "uw", rotation_only);
}

BranchVerdict walkPastTheWall(const Config& config, bool rotation_only) {
  return walkBeside(config, wallFromZ03(), rotation_only);
}

}  // namespace

TEST(CleanPrefix, BranchCheckCutsAtTheStartOfThePointCloudRun) {
  Config config;
  config.collision.prefix_margin = 0.5;
  config.collision.prefix_min_advance = 0.1;
  // Clearance 0.2 (0.1 units, 0.06 along z): 28 points at z = 0.3, 52 at z = 0.4, so it
  // marks the same frame 4 as eq. 6.
  config.collision.prefix_clearance = 0.2;
  const BranchVerdict v = walkPastTheWall(config, false);
  ASSERT_TRUE(v.collision_pc);
  EXPECT_EQ(v.prefix_frames, 2);
  // A rotation keeps all its frames (it is never cut).
  EXPECT_EQ(walkPastTheWall(config, true).prefix_frames, 10);
}

// The default clearance 0.5 (0.25 units): points within sqrt(0.25^2 - 0.08^2) = 0.237
// along z count, 4 z values x 4 rows = 16 at z = 0.1 and 14 x 4 = 56 at z = 0.2, so the
// wall is unsafe from frame 2, before eq. 6 fires. Margin 0.15 (0.075 units): z <= 0.125,
// frame 1, 2 frames; at margin 0.5 no prefix advances (z <= -0.05).
TEST(CleanPrefix, BranchCheckKeepsTheWiderClearance) {
  Config config;
  config.collision.prefix_min_advance = 0.1;
  config.collision.prefix_margin = 0.15;
  EXPECT_EQ(walkPastTheWall(config, false).prefix_frames, 2);
  config.collision.prefix_margin = 0.5;
  EXPECT_EQ(walkPastTheWall(config, false).prefix_frames, 0);
}

// Lost at frame 6. Behind a wall that eq. 6 caught (the wall of the tests above, with
// clearance 0.2 so it is unsafe from frame 4 only), the loss is the later event and the
// cut stays at frame 4: 2 frames. Lost at frame 3, before the wall: measured from
// frame 2 (z = 0.2), margin 0.5 (0.25 units): z <= -0.05, nothing. With no wall at all
// the loss alone is no evidence of where an obstacle is: no prefix.
TEST(CleanPrefix, BranchCheckCutsBeforeALostFrameOnlyWithAWallSeen) {
  Config config;
  config.collision.prefix_margin = 0.5;
  config.collision.prefix_min_advance = 0.1;
  config.collision.prefix_clearance = 0.2;
  auto walk = [&](CommittedSteps wall, int lost_from) {
    return walkBeside(config, std::move(wall), false, lost_from);
  };
  const BranchVerdict behind = walk(wallFromZ03(), 6);
  EXPECT_TRUE(behind.slam_lost && behind.collision_pc);
  EXPECT_EQ(behind.prefix_frames, 2);
  EXPECT_EQ(walk(wallFromZ03(), 3).prefix_frames, 0);
  const BranchVerdict blind = walk({}, 6);
  EXPECT_TRUE(blind.slam_lost);
  EXPECT_FALSE(blind.collision_pc || blind.collision_depth);
  EXPECT_EQ(blind.prefix_frames, 0);
}
