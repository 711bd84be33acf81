// Robust floor estimation (paper eq. 5, appendix A) on hand-built keyframes whose
// floor drifts in height and scale, as monocular SLAM drifts.
#include <gtest/gtest.h>

#include "valerant/explore/floor_estimator.h"

using namespace valerant;

namespace {

// Camera looking along +X with z up: optical x = -Y, y = -Z, z = +X.
Eigen::Isometry3d cameraAt(const Eigen::Vector3d& c) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  t.translation() = c;
  return t;
}

// Keyframe k of a drifting reconstruction: everything scaled by s = 1 + 0.1 k and
// lifted by 0.2 k. Floor points ahead of the camera (441 of them) and a wall.
struct DriftingKeyframe {
  double scale, lift;
  Eigen::Isometry3d pose;
  std::vector<CloudPoint> points;
};

DriftingKeyframe drifting(int k, bool with_floor = true) {
  DriftingKeyframe kf;
  kf.scale = 1 + 0.1 * k;
  kf.lift = 0.2 * k;
  const double x0 = k;  // the camera moves along X
  kf.pose = cameraAt({x0, 0, kf.lift + kf.scale * 1.0});
  auto add = [&](double x, double y, double z) {
    CloudPoint p;
    p.position = Eigen::Vector3f(x, y, z).cast<float>();
    p.confidence = 10;
    kf.points.push_back(p);
  };
  if (with_floor)
    for (int i = 0; i <= 20; ++i)
      for (int j = 0; j <= 20; ++j) add(x0 + kf.scale * (0.5 + 0.2 * i), kf.scale * (-2 + 0.2 * j), kf.lift);
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < 15; ++j)
      add(x0 + kf.scale * 5, kf.scale * (-1.5 + 0.2 * j), kf.lift + kf.scale * 0.14 * i);
  return kf;
}

FloorConfig rf(bool enabled) {
  FloorConfig c;
  c.enabled = enabled;
  return c;
}

}  // namespace

TEST(FloorEstimator, NormalisedHeightOfFloorCameraAndPoint) {
  FloorPlane f;
  f.q = {0, 0, 2};
  f.n = {0, 0, 1};
  f.c = {5, 5, 6};  // 4 above the floor
  EXPECT_DOUBLE_EQ(f.cameraHeight(), 4.0);
  EXPECT_DOUBLE_EQ(f.normalisedHeight({9, -3, 2}), 0.0);
  EXPECT_DOUBLE_EQ(f.normalisedHeight(f.c), 1.0);
  EXPECT_DOUBLE_EQ(f.normalisedHeight({0, 0, 3}), 0.25);
}

TEST(FloorEstimator, FollowsADriftingFloorWhereAFixedReferenceFails) {
  FloorEstimator robust(rf(true), Eigen::Vector3d::UnitZ(), 4.0);
  FloorEstimator fixed(rf(false), Eigen::Vector3d::UnitZ(), 4.0);
  for (int k = 0; k <= 5; ++k) {
    const DriftingKeyframe kf = drifting(k);
    const FloorPlane a = robust.update(kf.points, kf.pose);
    const FloorPlane b = fixed.update(kf.points, kf.pose);
    ASSERT_TRUE(a.reliable) << "keyframe " << k;
    EXPECT_GE(a.support, 300);
    const Eigen::Vector3d floor_point(k + 1.0, 0.3, kf.lift);
    EXPECT_NEAR(a.normalisedHeight(floor_point), 0.0, 1e-6) << "keyframe " << k;
    EXPECT_NEAR(a.cameraHeight(), kf.scale, 1e-6);
    if (k == 5) {
      // Fixed floor at z = 0 from keyframe 0; the drifted floor is at z = 1 and the
      // camera at z = 2.5: h = 1 / 2.5 = 0.4, inside the body band [0.18, 1.19]: a
      // false obstacle right where the floor is.
      EXPECT_NEAR(b.normalisedHeight(floor_point), 0.4, 1e-6);
    }
  }
}

TEST(FloorEstimator, FacingAWallPropagatesTheLastReliableRelation) {
  FloorEstimator robust(rf(true), Eigen::Vector3d::UnitZ(), 4.0);
  const DriftingKeyframe seen = drifting(2);
  ASSERT_TRUE(robust.update(seen.points, seen.pose).reliable);
  // Next keyframe sees only the wall (225 points < 300, and vertical): propagate.
  DriftingKeyframe wall_only = drifting(2, /*with_floor=*/false);
  wall_only.pose.translation().x() += 0.5;
  const FloorPlane p = robust.update(wall_only.points, wall_only.pose);
  EXPECT_FALSE(p.reliable);
  EXPECT_NEAR(p.cameraHeight(), seen.scale, 1e-6);         // the relation's distance (float points)
  EXPECT_NEAR(p.normalisedHeight({3.5, 0, 0.4}), 0.0, 1e-6);  // the floor under it
  EXPECT_TRUE(p.n.isApprox(Eigen::Vector3d::UnitZ()));
}

TEST(FloorEstimator, RejectsASteepPlaneAndTooLittleSupport) {
  FloorConfig config = rf(true);
  config.lower_envelope_fraction = 1.0;  // every point is a candidate: test the checks alone
  FloorEstimator estimator(config, Eigen::Vector3d::UnitZ(), 4.0);
  // A 45-degree-plus slope: |n . up| = cos(50 deg) = 0.64 < 0.7, with 441 points.
  std::vector<CloudPoint> slope;
  const double t = std::tan(50 * M_PI / 180);
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) {
      CloudPoint p;
      p.position = Eigen::Vector3f(1 + 0.1 * i, -1 + 0.1 * j, -3 + t * 0.1 * i);
      p.confidence = 10;
      slope.push_back(p);
    }
  EXPECT_FALSE(estimator.update(slope, cameraAt({0, 0, 0})).reliable);
  // A good floor with only 200 confident points is not enough either.
  std::vector<CloudPoint> sparse;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 10; ++j) {
      CloudPoint p;
      p.position = Eigen::Vector3f(1 + 0.1 * i, -1 + 0.2 * j, -1);
      p.confidence = 10;
      sparse.push_back(p);
    }
  EXPECT_FALSE(estimator.update(sparse, cameraAt({0, 0, 0})).reliable);
  // ... and low-confidence points do not count.
  for (auto& p : slope) p.confidence = 1;
  EXPECT_EQ(estimator.update(slope, cameraAt({0, 0, 0})).support, 0);
}

TEST(FloorEstimator, FloorIsUnknownUntilOneIsAccepted) {
  FloorEstimator robust(rf(true), Eigen::Vector3d::UnitZ(), 4.0);
  EXPECT_FALSE(robust.at(cameraAt({0, 0, 1})).known);
  // A wall alone (225 points, vertical) is rejected: still unknown.
  const DriftingKeyframe wall_only = drifting(0, /*with_floor=*/false);
  EXPECT_FALSE(robust.update(wall_only.points, wall_only.pose).known);
  const DriftingKeyframe seen = drifting(0);
  EXPECT_TRUE(robust.update(seen.points, seen.pose).known);
  EXPECT_TRUE(robust.at(cameraAt({1, 0, 1})).known);
}

namespace {

// A keyframe whose lowest points are a ledge top 0.25 below the camera (441 points):
// what a camera closing in on a wall with a ledge sees once no floor is left in view.
std::vector<CloudPoint> ledgeSeenFrom(const Eigen::Vector3d& c) {
  std::vector<CloudPoint> points;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) {
      CloudPoint p;
      p.position = Eigen::Vector3f(c.x() + 0.3 + 0.02 * i, c.y() - 0.2 + 0.02 * j, c.z() - 0.25);
      p.confidence = 10;
      points.push_back(p);
    }
  return points;
}

}  // namespace

TEST(FloorEstimator, ALedgeFarAboveTheFloorIsNotTakenForIt) {
  FloorEstimator robust(rf(true), Eigen::Vector3d::UnitZ(), 4.0);
  const DriftingKeyframe seen = drifting(2);  // floor 1.2 below the camera
  ASSERT_TRUE(robust.update(seen.points, seen.pose).reliable);
  // The ledge fits well (441 inliers, level) but at 0.25 / 1.2 = 0.21 of the floor's
  // distance, beyond the 1 / 1.5 allowed: the floor 1.2 below is propagated.
  Eigen::Isometry3d pose = seen.pose;
  pose.translation().x() += 0.5;
  const FloorPlane p = robust.update(ledgeSeenFrom(pose.translation()), pose);
  EXPECT_FALSE(p.reliable);
  EXPECT_EQ(p.support, 441);
  EXPECT_NEAR(p.cameraHeight(), 1.2, 1e-6);
}

TEST(FloorEstimator, ThreeKeyframesAgreeingOnANewDistanceRelock) {
  FloorEstimator robust(rf(true), Eigen::Vector3d::UnitZ(), 4.0);
  const DriftingKeyframe seen = drifting(2);
  ASSERT_TRUE(robust.update(seen.points, seen.pose).reliable);
  Eigen::Isometry3d pose = seen.pose;
  for (int k = 1; k <= 3; ++k) {
    pose.translation().x() += 0.5;
    const FloorPlane p = robust.update(ledgeSeenFrom(pose.translation()), pose);
    // Keyframes 1 and 2 of the jump propagate 1.2; the third takes the new 0.25.
    EXPECT_EQ(p.reliable, k == 3) << "keyframe " << k;
    EXPECT_NEAR(p.cameraHeight(), k == 3 ? 0.25 : 1.2, 1e-5) << "keyframe " << k;
  }
  // The relation is now 0.25: the next agreeing fit is accepted at once.
  pose.translation().x() += 0.5;
  EXPECT_TRUE(robust.update(ledgeSeenFrom(pose.translation()), pose).reliable);
}
