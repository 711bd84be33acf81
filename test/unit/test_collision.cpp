// Collision tests (paper eqs. 6 and 7) on a hand-built corridor: floor z = 0, camera
// 1 unit above it (kappa = 1), a wall across x = 3.
#include <gtest/gtest.h>

#include <cmath>

#include "level_walk.h"
#include "valerant/explore/depth_collision.h"
#include "valerant/explore/point_cloud_collision.h"

using namespace valerant;

namespace {

using test::floorUnder;
using test::track;

// Wall points on x = 3, |y| <= 1, z in [0, 2], spaced `step`; h = z (camera height 1).
std::vector<HeightedPoint> wall(double step, float confidence = 10) {
  std::vector<HeightedPoint> points;
  for (double y = -1; y <= 1 + 1e-9; y += step)
    for (double z = 0; z <= 2 + 1e-9; z += step) points.push_back({{3, y, z}, z, confidence});
  return points;
}

HeightedPoint at(double x, double y, double z) { return {{x, y, z}, z, 10}; }

}  // namespace

TEST(PointCloudCollision, ForwardThroughAWallFires) {
  const CollisionConfig config;
  // Dense wall: around (3, 0) the disc of radius 0.21 holds 21 columns x 51 body-band
  // rows = 1071 points >= 300: an immediate deep penetration.
  const auto dense = detectPointCloudCollision(wall(0.02), track(0, 5, 57), config, false);
  EXPECT_TRUE(dense.collision);
  EXPECT_GE(dense.occupied_max, 300);
  // Sparse wall (0.1 spacing): 5 columns x 10 rows = 50 >= 30 at every sample within
  // 0.21 of the wall (5 m / 57 frames = 0.088 apart: several in a row).
  const auto sparse = detectPointCloudCollision(wall(0.1), track(0, 5, 57), config, false);
  EXPECT_TRUE(sparse.collision);
  EXPECT_EQ(sparse.occupied_max, 50);
  EXPECT_LT(sparse.occupied_max, config.n_occ_immediate);
  // Sample 32 (x = 2.895) holds 3 columns x 10 rows = 30, sample 33 (x = 2.982) all 50:
  // the second consecutive sample at or above N_occ fires.
  EXPECT_EQ(sparse.sample, 33);
}

TEST(PointCloudCollision, RotationLowAndHighPointsAndNoiseDoNotFire) {
  const CollisionConfig config;
  // Rotating in place right against the wall: exempt.
  EXPECT_FALSE(detectPointCloudCollision(wall(0.02), track(3, 3, 57), config, true).collision);
  // Stopping 0.5 short of the wall: nothing inside the body cylinder.
  const auto short_of_wall = detectPointCloudCollision(wall(0.02), track(0, 2.5, 57), config, false);
  EXPECT_FALSE(short_of_wall.collision);
  EXPECT_EQ(short_of_wall.occupied_max, 0);
  // Floor points (h = 0.1) and a ceiling (h = 1.5) on the path are not body-level.
  std::vector<HeightedPoint> floor_and_ceiling;
  for (double x = 0; x <= 5; x += 0.02)
    for (double y = -0.2; y <= 0.2; y += 0.02) {
      floor_and_ceiling.push_back(at(x, y, 0.1));
      floor_and_ceiling.push_back(at(x, y, 1.5));
    }
  EXPECT_FALSE(detectPointCloudCollision(floor_and_ceiling, track(0, 5, 57), config, false).collision);
  // 35 points (>= 30) seen by only one sample of a sparse trajectory (0.5 apart):
  // isolated noise, not two consecutive samples.
  std::vector<HeightedPoint> cluster(35, at(2.0, 0.1, 0.5));
  const auto noise = detectPointCloudCollision(cluster, track(0, 5, 10), config, false);
  EXPECT_FALSE(noise.collision);
  EXPECT_EQ(noise.occupied_max, 35);
  // ... but 300 of them in one sample is a deep penetration.
  std::vector<HeightedPoint> deep(300, at(2.0, 0.1, 0.5));
  EXPECT_TRUE(detectPointCloudCollision(deep, track(0, 5, 10), config, false).collision);
  // Low-confidence points never count.
  EXPECT_FALSE(detectPointCloudCollision(wall(0.02, 3.9f), track(0, 5, 57), config, false).collision);
}

TEST(PointCloudCollision, ScaleDriftIsCancelledByNormalisation) {
  const CollisionConfig config;
  // The same scene reconstructed 3x larger: kappa = 3, wall at x = 9: same verdicts.
  std::vector<HeightedPoint> points;
  for (auto p : wall(0.1)) points.push_back({p.position * 3, p.h, p.confidence});
  std::vector<FloorPlane> samples;
  for (auto s : track(0, 5, 57)) {
    s.q *= 3;
    s.c *= 3;
    samples.push_back(s);
  }
  const auto scaled = detectPointCloudCollision(points, samples, config, false);
  EXPECT_TRUE(scaled.collision);
  EXPECT_EQ(scaled.occupied_max, 50);
}

TEST(PointCloudCollision, SeveralRadiiFromOneIndex) {
  CollisionConfig config;
  // Sample 33 (x = 2.982) of the sparse wall: at rho 0.21 the 5 columns |y| <= 0.2 x 10
  // body-band rows = 50; at 0.35 the 7 columns |y| <= 0.3 (0.3 < sqrt(0.35^2 - 0.018^2)
  // = 0.3495 < 0.4) = 70.
  const auto counts = bodyCylinderCounts(wall(0.1), track(0, 5, 57), config, {0.21, 0.35});
  ASSERT_EQ(counts.size(), 2u);
  EXPECT_EQ(counts[0][33], 50);
  EXPECT_EQ(counts[1][33], 70);
  // Each radius counts as if alone, for the paper's band and the stepped body.
  for (double step_height : {0.0, 0.45}) {
    config.step_height = step_height;
    const auto both = bodyCylinderCounts(wall(0.1), track(0, 5, 57), config, {0.21, 0.35});
    EXPECT_EQ(both[0], bodyCylinderCounts(wall(0.1), track(0, 5, 57), config, {0.21}).front());
    EXPECT_EQ(both[1], bodyCylinderCounts(wall(0.1), track(0, 5, 57), config, {0.35}).front());
  }
  EXPECT_TRUE(bodyCylinderCounts(wall(0.1), track(0, 5, 57), config, {}).empty());
}

TEST(DepthCollision, CentralMeanDepthUsesTheCentralThird) {
  cv::Mat depth(9, 9, CV_32F, cv::Scalar(10.f));
  depth(cv::Rect(3, 3, 3, 3)).setTo(2.f);
  depth.at<float>(4, 4) = std::nanf("");
  EXPECT_DOUBLE_EQ(centralMeanDepth(depth, 1.0 / 3), 2.0);
  EXPECT_TRUE(std::isnan(centralMeanDepth(cv::Mat(9, 9, CV_32F, cv::Scalar(std::nanf(""))), 1.0 / 3)));
}

namespace {

// Frames of a camera looking along +X moving from x0 to x1 toward the wall at x = 3;
// the rendered central depth is the distance to the wall (the WM shows the far side
// once through: depth 5 there).
std::vector<DepthSample> approach(double x0, double x1, int n) {
  std::vector<DepthSample> frames;
  for (const auto& f : track(x0, x1, n)) {
    const double x = f.c.x();
    frames.push_back({x < 3 ? 3 - x : 5.0, f, Eigen::Vector3d::UnitX()});
  }
  return frames;
}

}  // namespace

TEST(DepthCollision, WalkingIntoAWallFires) {
  const CollisionConfig config;
  const double d_fwd = 256.0 / 50;
  // 0 -> 5 in 57 frames: the wall is within 0.455 from x = 2.545 (frame index 29,
  // x = 2.632, depth 0.368) and the camera still goes 2.37 further, far above
  // s_min = 0.085 * 5.12 * 27 / 57 = 0.206.
  const DepthCollision hit = detectDepthCollision(approach(0, 5, 57), config, d_fwd);
  EXPECT_TRUE(hit.collision);
  EXPECT_EQ(hit.frame, 29);
}

TEST(DepthCollision, LookingAtACloseWallDoesNotFire) {
  const CollisionConfig config;
  const double d_fwd = 256.0 / 50;
  // Rotating in place 0.3 from the wall: near, but no forward motion.
  std::vector<DepthSample> frames;
  for (int i = 0; i < 57; ++i) {
    const double yaw = i * (M_PI / 2) / 57;
    frames.push_back({0.3, floorUnder(2.7), Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0)});
  }
  EXPECT_FALSE(detectDepthCollision(frames, config, d_fwd).collision);
  // Walking up to 1.0 from the wall and stopping: never within 0.455.
  const DepthCollision stop = detectDepthCollision(approach(0, 2.0, 57), config, d_fwd);
  EXPECT_FALSE(stop.collision);
  EXPECT_NEAR(stop.min_near_ratio, 1.0, 1e-9);
  // Moving backwards away from a close wall: Fwd < 0.
  EXPECT_FALSE(detectDepthCollision(approach(2.8, 1.0, 57), config, d_fwd).collision);
}
