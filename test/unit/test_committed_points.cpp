// CommittedPoints and BranchCheck's use of them: a wall beside the path that the
// branch's own camera never saw, mapped by an earlier committed step. Map frame = the
// first camera's optical frame (y down); the floor is y = 0.5, so kappa = 0.5 and the
// body radius rho = 0.21 is 0.105 map units. The camera walks z = 0 .. 0.9 in steps of
// 0.1. The wall: x = 0.08 (inside the body radius), y = 0.05 .. 0.35 in 4 rows
// (normalised heights 0.3 .. 0.9, inside [0.18, 1.19]).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "valerant/explore/branch_check.h"
#include "valerant/common/error.h"
#include "valerant/explore/committed_points.h"
#include "valerant/explore/step_support.h"
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

// The floor of a keyframe at the start camera: y = kFloorY below it.
FloorPlane startFloor() { return valerant::test::floorBelow(Eigen::Vector3d::Zero(), kFloorY); }

// One committed step holding `cloud`, its keyframe's floor `floor`.
CommittedSteps committedStep(const KeyframeCloud& cloud, const FloorPlane& floor) {
  CommittedPoints committed(Config().collision);
  committed.add({cloud}, {floor});
  return committed.points();
}

CommittedSteps wall(double z0, double z1) { return committedStep(wallCloud(z0, z1), startFloor()); }

// The kept steps' x coordinates, step by step.
std::vector<std::vector<float>> xs(const CommittedSteps& steps) {
  std::vector<std::vector<float>> out;
  for (const auto& step : steps) {
    out.emplace_back();
    for (const CommittedPoint& p : *step) out.back().push_back(p.position.x());
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
// start_occupied records them: z = -0.05 .. 0.05 every 0.01 is 11 values x 4 rows = 44
// points, all within 0.094 of the start axis; body_counts has one 0 per frame.
TEST(CommittedPoints, PointsBesideTheStartAreLeftOut) {
  const BranchVerdict v = walk(Config(), wall(-0.05, 0.05), false);
  EXPECT_FALSE(v.collision_pc);
  EXPECT_EQ(v.occupied_max, 0);
  EXPECT_EQ(v.start_occupied, 44);
  EXPECT_EQ(v.body_counts, std::vector<int>(10, 0));
  // A wall ahead is not beside the start.
  EXPECT_EQ(walk(Config(), wall(0.3, 0.9), false).start_occupied, 0);
}

// body_counts frame by frame for the wall from z = 0.3 to 0.9: at z_i the points with
// |z - z_i| <= 0.068 count, 4 rows each. z = 0 .. 0.2: none (the wall is 0.1 or more
// ahead); z = 0.3: 0.30 .. 0.36, 7 values = 28; z = 0.4 .. 0.8: 13 values = 52;
// z = 0.9: 0.84 .. 0.90, 7 values = 28.
TEST(CommittedPoints, BodyCountsFrameByFrame) {
  const BranchVerdict v = walk(Config(), wall(0.3, 0.9), false);
  EXPECT_EQ(v.body_counts, (std::vector<int>{0, 0, 0, 28, 52, 52, 52, 52, 52, 28}));
}

TEST(CommittedPoints, KeepsOnlyConfidentKeyframePoints) {
  KeyframeCloud a, b;
  a.points = {{Eigen::Vector3f(1, 0, 0), {}, 10.f}, {Eigen::Vector3f(2, 0, 0), {}, 1.f}};
  b.points = {{Eigen::Vector3f(3, 0, 0), {}, 4.f}};
  CommittedPoints committed(Config().collision);
  EXPECT_TRUE(committed.points().empty());
  committed.add({a, b}, {startFloor(), startFloor()});
  EXPECT_EQ(xs(committed.points()), (std::vector<std::vector<float>>{{1.f, 3.f}}));
}

// previous_steps = 2 after three steps with one point each (x = 1, 2, 3): the two
// latest, oldest first. 0 keeps nothing.
TEST(CommittedPoints, KeepsTheLatestSteps) {
  CollisionConfig config;
  config.previous_steps = 2;
  CommittedPoints committed(config);
  for (float x : {1.f, 2.f, 3.f}) committed.add({pointAtX(x, 10.f)}, {startFloor()});
  EXPECT_EQ(committed.steps(), 2);
  EXPECT_EQ(xs(committed.points()), (std::vector<std::vector<float>>{{2.f}, {3.f}}));

  config.previous_steps = 0;
  CommittedPoints none(config);
  none.add({pointAtX(1.f, 10.f)}, {startFloor()});
  EXPECT_EQ(none.steps(), 0);
  EXPECT_TRUE(none.points().empty());
}

// A checkpoint holds a copy: steps committed after it do not reach it, and the step
// both hold is one set in memory, not two.
TEST(CommittedPoints, ACopyIsACheckpoint) {
  CommittedPoints committed(Config().collision);
  committed.add({pointAtX(1.f, 10.f)}, {startFloor()});
  const CommittedPoints saved = committed;
  committed.add({pointAtX(2.f, 10.f)}, {startFloor()});
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
    c->add({wallCloud(0.3, 0.9)}, {startFloor()});
    c->add({pointAtX(5.f, 10.f)}, {startFloor()});
  }
  const BranchVerdict missed = walk(last_only, one.points(), false);
  EXPECT_FALSE(missed.collision_pc);
  EXPECT_EQ(missed.occupied_max, 0);
  const BranchVerdict seen = walk(Config(), all.points(), false);
  EXPECT_TRUE(seen.collision_pc);
  EXPECT_EQ(seen.occupied_max, 52);
}

// Heights from each point's own keyframe floor (eq. 5). A floor patch at y = 0.4 under
// the path (x = -0.05, 0, 0.05; z = 0.3 .. 0.9 every 0.01), as a view whose scale came
// out small places the floor: from the branch's floor y = 0.5 it stands h = 0.1 / 0.5 =
// 0.2 high, inside [0.18, 1.19]. At an inner sample the points within 0.105 of the axis
// are x = 0 with |dz| <= 0.10 (21) and x = +-0.05 with |dz| <= 0.09 (19 each): 59. The
// keyframe that saw it fitted its floor on it (y = 0.4): h = 0, and with
// committed_heights = own_floor nothing counts. The default measures from the
// branch's first floor whatever the keyframe's.
TEST(CommittedPoints, OwnFloorHeightsComeFromTheirKeyframesFloor) {
  KeyframeCloud patch;
  for (int i = 30; i <= 90; ++i)
    for (float x : {-0.05f, 0.f, 0.05f}) patch.points.push_back({Eigen::Vector3f(x, 0.4f, 0.01f * i), {}, 10.f});
  Config own_floor;
  own_floor.collision.committed_heights = "own_floor";
  const BranchVerdict raised = walk(own_floor, committedStep(patch, startFloor()), false);
  EXPECT_TRUE(raised.collision_pc);
  EXPECT_EQ(raised.occupied_max, 59);
  const FloorPlane own = valerant::test::floorBelow(Eigen::Vector3d::Zero(), 0.4);
  const BranchVerdict flat = walk(own_floor, committedStep(patch, own), false);
  EXPECT_FALSE(flat.collision_pc);
  EXPECT_EQ(flat.occupied_max, 0);
  EXPECT_EQ(walk(Config(), committedStep(patch, own), false).occupied_max, 59);
  // A keyframe without a known floor: the branch's first floor measures it.
  FloorPlane unknown = own;
  unknown.known = false;
  const CommittedSteps step = committedStep(patch, unknown);
  EXPECT_TRUE(std::isnan(step.front()->front().h));
  EXPECT_EQ(walk(own_floor, step, false).occupied_max, 59);
}

// BranchCheck copies only the committed points some body can reach (body_reach.h); the
// counts must be those of every point. The wall of WallBesideThePathIsACollision plus
// 20,000 points over a 40 x 40 area around the walk and 2,000 around its path, at
// heights y -1 .. 1 (h = (0.5 - y) / 0.5 from the branch's floor, -1 .. 3): the paper's
// counts equal a brute-force count over every point (within rho kappa of the axis x = 0,
// z = z_i, h in [eta_low, eta_high], none beside the start); the stepped body's equal
// steppedBodyCounts over every point.
TEST(CommittedPoints, PointsOutOfEveryBodysReachChangeNoCount) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> anywhere(-20, 20), height(-1, 1), beside(-0.3f, 0.3f), along(-0.5f, 1.5f);
  KeyframeCloud cloud = wallCloud(0.3, 0.9);
  for (int i = 0; i < 20000; ++i) cloud.points.push_back({{anywhere(rng), height(rng), anywhere(rng)}, {}, 10.f});
  for (int i = 0; i < 2000; ++i) cloud.points.push_back({{beside(rng), height(rng), along(rng)}, {}, 10.f});
  const CommittedSteps steps = committedStep(cloud, startFloor());

  std::vector<FloorPlane> floors;
  for (int i = 0; i < 10; ++i) floors.push_back(valerant::test::floorBelow({0, 0, 0.1 * i}, kFloorY));
  const Config paper;
  const double r = paper.collision.body_radius * kFloorY;
  std::vector<HeightedPoint> counted;  // every point but those beside the start
  for (const CommittedPoint& p : *steps.front()) {
    const Eigen::Vector3d x = p.position.cast<double>();
    if (x.x() * x.x() + x.z() * x.z() > r * r) counted.push_back({x, (kFloorY - x.y()) / kFloorY, p.confidence});
  }
  std::vector<int> expected;
  for (const FloorPlane& f : floors) {
    int n = 0;
    for (const HeightedPoint& p : counted)
      n += f.axisDistanceSquared(p.position) <= r * r && countedInBody(p.h, p.confidence, paper.collision);
    expected.push_back(n);
  }
  const BranchVerdict v = walk(paper, steps, false);
  EXPECT_EQ(v.body_counts, expected);
  EXPECT_GT(*std::max_element(expected.begin(), expected.end()), paper.collision.n_occ);  // not a scene of zeros

  Config stepped;
  stepped.collision.step_height = 0.45;
  EXPECT_EQ(walk(stepped, steps, false).body_counts,
            steppedBodyCounts(counted, floors, stepped.collision, stepped.collision.body_radius).counts);
}

// Carving (collision.carve_committed_views). Frames of 320 x 240 at 90 degrees: the
// rebuilt views are 160 x 120 with f = 80, c = (80, 60), so a point (x, y, z) in a
// camera's frame lands on pixel (80 + 80 x / z, 60 + 80 y / z).
namespace {

const CameraIntrinsics kFrame = CameraIntrinsics::fromHorizontalFov(320, 240, 90);

Config carving(int views) {
  Config c;
  c.collision.carve_committed_views = views;
  return c;
}

// A keyframe at `camera_to_map` holding `points` (camera frame), confidence 10.
KeyframeCloud keyframeSeeing(const Eigen::Isometry3d& camera_to_map, const std::vector<Eigen::Vector3f>& points) {
  KeyframeCloud cloud;
  cloud.camera_to_map = camera_to_map;
  for (const Eigen::Vector3f& p : points) cloud.points.push_back({camera_to_map.cast<float>() * p, {}, 10.f});
  return cloud;
}

// A wall filling a view at depth `depth`: one point on each of its 160 x 120 pixel centres.
KeyframeCloud keyframeFacingAWall(const Eigen::Isometry3d& camera_to_map, float depth) {
  std::vector<Eigen::Vector3f> points;
  for (int v = 0; v < 120; ++v)
    for (int u = 0; u < 160; ++u)
      points.emplace_back((u + 0.5f - 80) / 80 * depth, (v + 0.5f - 60) / 80 * depth, depth);
  return keyframeSeeing(camera_to_map, points);
}

}  // namespace

// Pixel (80 + 80 * 0.5 / 2, 60 + 80 * 0.25 / 2) = (100, 70) holds the nearer of two points
// on its ray (depth 2, not 4); a point under the confidence cut, one behind the camera and
// one outside the image leave their pixels unknown.
TEST(CommittedPoints, AKeyframesViewIsRebuiltFromItsCloud) {
  KeyframeCloud kf = keyframeSeeing(Eigen::Isometry3d::Identity(),
                                    {{0.5f, 0.25f, 2.f}, {1.f, 0.5f, 4.f}, {0, 0, -1.f}, {10.f, 0, 1.f}, {0, 0, 3.f}});
  kf.points.back().confidence = 1.f;  // (0, 0, 3) on pixel (80, 60): not confident
  const DepthView view = depthViewOfCloud(kf, CameraIntrinsics::fromHorizontalFov(160, 120, 90), 4.0);
  ASSERT_EQ(view.depth.size(), cv::Size(160, 120));
  EXPECT_FLOAT_EQ(view.depth.at<float>(70, 100), 2.f);
  EXPECT_EQ(cv::countNonZero(view.depth == view.depth), 1);  // NaN != NaN: one pixel known
}

// A stray point 1 ahead of keyframe A; keyframes B and C stand at A's place and see a wall
// 3 ahead on its pixel (80, 60): 3 > 1.3 x 1, each sees past it. A's own view sees it
// there (support 1). After B: through 1, support 1, kept (through must exceed support);
// after C: through 2 > 1, carved at k = 1 and 2, kept at k = 3. The wall points (3
// ahead) are hidden behind the stray in A's view (1 < 0.7 x 3) and held by B and C.
// In the other order (B, C, then A) the new step's stray point meets the kept views at once.
TEST(CommittedPoints, PointsTheCommittedViewsSawPastAreCarved) {
  const Eigen::Isometry3d here = Eigen::Isometry3d::Identity();
  const KeyframeCloud a = keyframeSeeing(here, {{0, 0, 1.f}});
  const KeyframeCloud wall = keyframeSeeing(here, {{0, 0, 3.f}});
  for (const int k : {1, 2, 3}) {
    CommittedPoints committed(carving(k).collision, kFrame);
    committed.add({a}, {startFloor()});
    committed.add({wall}, {startFloor()});
    EXPECT_EQ(committed.carvedPoints(), 0u) << k;
    committed.add({wall}, {startFloor()});
    EXPECT_EQ(committed.carvedPoints(), k <= 2 ? 1u : 0u) << k;
    EXPECT_EQ(committed.points().front()->size(), k <= 2 ? 0u : 1u) << k;
    EXPECT_EQ(committed.points()[1]->size(), 1u) << k;

    CommittedPoints reversed(carving(k).collision, kFrame);
    reversed.add({wall}, {startFloor()});
    reversed.add({wall}, {startFloor()});
    reversed.add({a}, {startFloor()});
    EXPECT_EQ(reversed.carvedPoints(), k <= 2 ? 1u : 0u) << k;
    EXPECT_EQ(reversed.points().back()->size(), k <= 2 ? 0u : 1u) << k;
  }
  CommittedPoints off(Config().collision, kFrame);
  for (const KeyframeCloud& kf : {a, wall, wall}) off.add({kf}, {startFloor()});
  EXPECT_EQ(off.carvedPoints(), 0u);
  EXPECT_EQ(off.points().front()->size(), 1u);
}

// Evidence gathered after a checkpoint does not reach it.
TEST(CommittedPoints, ACheckpointKeepsItsOwnEvidence) {
  const Eigen::Isometry3d here = Eigen::Isometry3d::Identity();
  CommittedPoints committed(carving(2).collision, kFrame);
  committed.add({keyframeSeeing(here, {{0, 0, 1.f}})}, {startFloor()});
  committed.add({keyframeSeeing(here, {{0, 0, 3.f}})}, {startFloor()});
  const CommittedPoints saved = committed;
  committed.add({keyframeSeeing(here, {{0, 0, 3.f}})}, {startFloor()});
  EXPECT_EQ(committed.carvedPoints(), 1u);
  EXPECT_EQ(saved.carvedPoints(), 0u);
  EXPECT_EQ(saved.points().front()->size(), 1u);
}

// The wall of WallBesideThePathIsACollision (52 points at its fullest sample), and a
// later step with two keyframes 2 behind the start (0, 0, -2) facing a wall 10 away
// (at z = 8). The wall's points stand 2.3 to 2.9 ahead of them, inside their views
// (pixel row 60 + 80 x 0.35 / 2.3 = 72 at most), where they read 10 > 1.3 x 2.9: two
// views see past every point, and at most one (the wall's own keyframe) sees it there.
// With k = 2 none is left in the body (the walk is clear); k = 3 keeps all 52.
TEST(CommittedPoints, AWallTheLaterViewsSawPastIsNoCollision) {
  Eigen::Isometry3d behind = Eigen::Isometry3d::Identity();
  behind.translation() = Eigen::Vector3d(0, 0, -2);
  KeyframeCloud near_wall = wallCloud(0.3, 0.9);
  near_wall.camera_to_map = Eigen::Isometry3d::Identity();
  const KeyframeCloud far = keyframeFacingAWall(behind, 10.f);
  for (const int k : {2, 3}) {
    CommittedPoints committed(carving(k).collision, kFrame);
    committed.add({near_wall}, {startFloor()});
    committed.add({far, far}, {startFloor(), startFloor()});
    const BranchVerdict v = walk(carving(k), committed.points(), false);
    EXPECT_EQ(v.occupied_max, k == 2 ? 0 : 52) << k;
    EXPECT_EQ(v.collision_pc, k == 3) << k;
  }
}

TEST(CommittedPoints, CarvingWithoutTheFramesIntrinsicsIsAnErrorNamingTheKey) {
  try {
    CommittedPoints committed(carving(2).collision);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.input(), "collision.carve_committed_views");
  }
}

TEST(CommittedPoints, KeyframesAndFloorsMustPair) {
  CommittedPoints committed(Config().collision);
  EXPECT_THROW(committed.add({pointAtX(1.f, 10.f)}, {}), InputError);
}
