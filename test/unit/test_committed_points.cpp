// CommittedPoints and BranchCheck's use of them: a wall beside the path that the
// branch's own camera never saw, mapped by an earlier committed step. Map frame = the
// first camera's optical frame (y down); the floor is y = 0.5, so kappa = 0.5 and the
// body radius rho = 0.21 is 0.105 map units. The camera walks z = 0 .. 0.9 in steps of
// 0.1. The wall: x = 0.08 (inside the body radius), y = 0.05 .. 0.35 in 4 rows
// (normalised heights 0.3 .. 0.9, inside [0.18, 1.19]).
#include <gtest/gtest.h>

#include "valerant/explore/branch_check.h"
#include "valerant/explore/committed_points.h"
#include "walking_branch.h"

using namespace valerant;
using valerant::test::trackedAtZ;

namespace {

constexpr double kFloorY = 0.5;

// Wall points at x = 0.08 for z in [z0, z1] every 0.01, 4 rows, confidence 10.
KeyframeCloud wallCloud(double z0, double z1) {
  KeyframeCloud cloud;
  for (double z = z0; z <= z1 + 1e-9; z += 0.01)
    for (double y : {0.05, 0.15, 0.25, 0.35})
      cloud.points.push_back({Eigen::Vector3f(0.08f, static_cast<float>(y), static_cast<float>(z)), {}, 10.f});
  return cloud;
}

CommittedSteps wall(double z0, double z1) {
  return {std::make_shared<std::vector<CloudPoint>>(wallCloud(z0, z1).points)};
}

// The kept steps' x coordinates, step by step.
std::vector<std::vector<float>> xs(const CommittedSteps& steps) {
  std::vector<std::vector<float>> out;
  for (const auto& step : steps) {
    out.emplace_back();
    for (const CloudPoint& p : *step) out.back().push_back(p.position.x());
  }
  return out;
}

KeyframeCloud pointAtX(float x, float confidence) {
  KeyframeCloud cloud;
  cloud.points = {{Eigen::Vector3f(x, 0, 0), {}, confidence}};
  return cloud;
}

// A forward branch with no keyframe points of its own.
BranchVerdict walk(const Config& config, CommittedSteps previous, bool rotation_only) {
  BranchCheck check(config, std::move(previous));
  for (int i = 0; i < 10; ++i) {
    const TrackedFrame f = trackedAtZ(0.1 * i);
    check.add(f, nullptr, valerant::test::floorBelow(f.camera_to_map.translation(), kFloorY));
  }
  return check.finish(rotation_only ? "jq" : "uw", rotation_only);
}

}  // namespace

// Wall from z = 0.3 to 0.9. At a sample z_i the wall points within 0.105 of the axis
// have |z - z_i| <= sqrt(0.105^2 - 0.08^2) = 0.068: 13 z values x 4 rows = 52 >= N_occ
// (30) at every sample from z = 0.4 on, so two consecutive samples fire.
TEST(CommittedPoints, WallBesideThePathIsACollision) {
  const BranchVerdict with = walk(Config(), wall(0.3, 0.9), false);
  EXPECT_TRUE(with.collision_pc);
  EXPECT_EQ(with.occupied_max, 52);
  // The branch's own points alone show nothing.
  EXPECT_FALSE(walk(Config(), {}, false).collision_pc);
  Config off;
  off.collision.previous_steps = 0;
  EXPECT_FALSE(walk(off, wall(0.3, 0.9), false).collision_pc);
}

TEST(CommittedPoints, RotationsStayExempt) { EXPECT_FALSE(walk(Config(), wall(0.3, 0.9), true).collision_pc); }

// Standing beside a wall: points within the body radius at the start (z = -0.05 ..
// 0.05: at most sqrt(0.08^2 + 0.05^2) = 0.094 <= 0.105 from the start axis) are left
// out, though the sample at z = 0.1 would otherwise count them (distance 0.094 again).
TEST(CommittedPoints, PointsBesideTheStartAreLeftOut) {
  const BranchVerdict v = walk(Config(), wall(-0.05, 0.05), false);
  EXPECT_FALSE(v.collision_pc);
  EXPECT_EQ(v.occupied_max, 0);
}

TEST(CommittedPoints, KeepsOnlyConfidentKeyframePoints) {
  KeyframeCloud a, b;
  a.points = {{Eigen::Vector3f(1, 0, 0), {}, 10.f}, {Eigen::Vector3f(2, 0, 0), {}, 1.f}};
  b.points = {{Eigen::Vector3f(3, 0, 0), {}, 4.f}};
  CommittedPoints committed(Config().collision);
  EXPECT_TRUE(committed.points().empty());
  committed.add({a, b});
  EXPECT_EQ(xs(committed.points()), (std::vector<std::vector<float>>{{1.f, 3.f}}));
}

// previous_steps = 2 after three steps with one point each (x = 1, 2, 3): the two
// latest, oldest first. 0 keeps nothing.
TEST(CommittedPoints, KeepsTheLatestSteps) {
  CollisionConfig config;
  config.previous_steps = 2;
  CommittedPoints committed(config);
  for (float x : {1.f, 2.f, 3.f}) committed.add({pointAtX(x, 10.f)});
  EXPECT_EQ(committed.steps(), 2);
  EXPECT_EQ(xs(committed.points()), (std::vector<std::vector<float>>{{2.f}, {3.f}}));

  config.previous_steps = 0;
  CommittedPoints none(config);
  none.add({pointAtX(1.f, 10.f)});
  EXPECT_EQ(none.steps(), 0);
  EXPECT_TRUE(none.points().empty());
}

// A checkpoint holds a copy: steps committed after it do not reach it, and the step
// both hold is one set in memory, not two.
TEST(CommittedPoints, ACopyIsACheckpoint) {
  CommittedPoints committed(Config().collision);
  committed.add({pointAtX(1.f, 10.f)});
  const CommittedPoints saved = committed;
  committed.add({pointAtX(2.f, 10.f)});
  EXPECT_EQ(xs(committed.points()), (std::vector<std::vector<float>>{{1.f}, {2.f}}));
  EXPECT_EQ(xs(saved.points()), (std::vector<std::vector<float>>{{1.f}}));
  EXPECT_EQ(saved.points()[0].get(), committed.points()[0].get());
}

// The wall of WallBesideThePathIsACollision was mapped two steps ago; the last step
// mapped only a point far away (x = 5). Keeping one step misses the wall (occupied_max
// 0); the default keeps both and the same 52 points fire.
TEST(CommittedPoints, AWallMappedTwoStepsAgoStillCounts) {
  Config last_only;
  last_only.collision.previous_steps = 1;
  CommittedPoints one(last_only.collision), all(Config().collision);
  for (CommittedPoints* c : {&one, &all}) {
    c->add({wallCloud(0.3, 0.9)});
    c->add({pointAtX(5.f, 10.f)});
  }
  const BranchVerdict missed = walk(last_only, one.points(), false);
  EXPECT_FALSE(missed.collision_pc);
  EXPECT_EQ(missed.occupied_max, 0);
  const BranchVerdict seen = walk(Config(), all.points(), false);
  EXPECT_TRUE(seen.collision_pc);
  EXPECT_EQ(seen.occupied_max, 52);
}
