// Free-space evidence against eq. 6's points ([ours], collision.see_through_frames,
// free_space_evidence.h, branch_check.h): hand-worked views and walks.
#include <gtest/gtest.h>

#include <limits>

#include "valerant/common/error.h"
#include "valerant/explore/branch_check.h"
#include "valerant/explore/committed_points.h"
#include "valerant/explore/free_space_evidence.h"
#include "walking_branch.h"

using namespace valerant;
using valerant::test::edgeAt;
using valerant::test::floorBelow;
using valerant::test::trackedAtZ;

namespace {

// 4 x 4 pixels, 90 degrees: fx = fy = 0.5 * 4 / tan(45) = 2, cx = cy = 2.
const CameraIntrinsics kFour = CameraIntrinsics::fromHorizontalFov(4, 4, 90);

// A camera at (0, 0, z) looking along +z whose every pixel reads `depth`.
DepthView viewAt(double z, float depth) {
  DepthView v;
  v.map_to_camera.translation() = Eigen::Vector3d(0, 0, -z);
  v.depth = cv::Mat(4, 4, CV_32FC1, cv::Scalar(depth));
  return v;
}

}  // namespace

// The camera at the origin reads 10 everywhere; tau 0.3. A point 5 ahead projects to
// pixel (2, 2): 10 > 1.3 * 5 = 6.5, seen through. 9 ahead: |10 - 9| = 1 <= 2.7, seen
// there. 20 ahead: 10 < 0.7 * 20 = 14, hidden behind the surface: no evidence; so is a
// point behind the camera, and one at x = 10, z = 5 (u = 2 * 10 / 5 + 2 = 6, outside).
TEST(FreeSpaceEvidence, AViewSeesPastThroughOrHidesAPoint) {
  const std::vector<DepthView> one = {viewAt(0, 10)};
  auto at = [&](double x, double z) { return freeSpaceEvidence({x, 0, z}, one, kFour, 0.3); };
  EXPECT_EQ(at(0, 5).through, 1);
  EXPECT_EQ(at(0, 5).support, 0);
  EXPECT_EQ(at(0, 9).through, 0);
  EXPECT_EQ(at(0, 9).support, 1);
  for (const FreeSpaceEvidence e : {at(0, 20), at(0, -5), at(10, 5)}) {
    EXPECT_EQ(e.through, 0);
    EXPECT_EQ(e.support, 0);
  }
  // An unknown depth is no evidence either.
  std::vector<DepthView> unknown = {viewAt(0, std::numeric_limits<float>::quiet_NaN())};
  EXPECT_EQ(freeSpaceEvidence({0, 0, 5}, unknown, kFour, 0.3).through, 0);
}

// The point (0, 0, 5): the camera at the origin reading 10 sees past it; one at z = -5
// reading 10 sees it where it is (10 away). One view each way: not seen through, the
// support holds it. Two views past it against one: seen through at min_frames 2, not 3.
TEST(FreeSpaceEvidence, TheViewsThatSawAPointHoldItAgainstThoseThatSawPast) {
  const Eigen::Vector3d p(0, 0, 5);
  const FreeSpaceEvidence even = freeSpaceEvidence(p, {viewAt(0, 10), viewAt(-5, 10)}, kFour, 0.3);
  EXPECT_EQ(even.through, 1);
  EXPECT_EQ(even.support, 1);
  EXPECT_FALSE(even.seenThrough(1));
  const FreeSpaceEvidence more = freeSpaceEvidence(p, {viewAt(0, 10), viewAt(1, 10), viewAt(-5, 10)}, kFour, 0.3);
  EXPECT_EQ(more.through, 2);  // from z = 1 the point is 4 away: 10 > 5.2
  EXPECT_TRUE(more.seenThrough(2));
  EXPECT_FALSE(more.seenThrough(3));
  EXPECT_FALSE(more.seenThrough(0));  // 0 = off
}

// A frame's view keeps only its confident depth, every second pixel a side.
TEST(FreeSpaceEvidence, AViewKeepsTheConfidentDepthAtHalfResolution) {
  cv::Mat depth(4, 4, CV_32FC1, cv::Scalar(3)), confidence(4, 4, CV_32FC1, cv::Scalar(10));
  confidence.at<float>(0, 0) = 2;  // under the 4.0 cut
  Eigen::Isometry3d camera_to_map = Eigen::Isometry3d::Identity();
  camera_to_map.translation() = Eigen::Vector3d(1, 2, 3);
  const DepthView v = depthViewOf(camera_to_map, depth, confidence, 4.0, 2);
  ASSERT_EQ(v.depth.size(), cv::Size(2, 2));
  EXPECT_TRUE(std::isnan(v.depth.at<float>(0, 0)));
  EXPECT_EQ(v.depth.at<float>(1, 1), 3.f);
  EXPECT_TRUE((v.map_to_camera * Eigen::Vector3d(1, 2, 3)).isZero());
}

// A frame without its confidence cannot say which depth to trust: a clear error, not an
// image of unknowns (an empty mask would have set every pixel).
TEST(FreeSpaceEvidence, ADepthWithoutItsConfidenceIsAnInputError) {
  const cv::Mat depth(4, 4, CV_32FC1, cv::Scalar(3));
  EXPECT_THROW(depthViewOf(Eigen::Isometry3d::Identity(), depth, cv::Mat(), 4.0, 2), InputError);
  EXPECT_THROW(depthViewOf(Eigen::Isometry3d::Identity(), depth, cv::Mat(2, 2, CV_32FC1), 4.0, 2), InputError);
}

namespace {

// Rho 0.30 (0.15 units at kappa 0.5), no prefixes; `frames` for see_through_frames.
Config seeThroughConfig(int frames) {
  Config config;
  config.collision.body_radius = 0.30;
  config.collision.prefix_commits = false;
  config.collision.see_through_frames = frames;
  return config;
}

// The camera walks z = 0, 0.1 .. 0.9 (kappa 0.5) toward the cluster; every frame's
// confident depth (32 x 24 pixels, 90 degrees) is `depth_at(z)` at every pixel.
template <typename DepthAt>
BranchVerdict walkToward(const Config& config, DepthAt depth_at) {
  // 40 committed points in the path at z = 0.6 (edgeAt, walking_branch.h).
  BranchCheck check(config, edgeAt(0, 0.6f));
  for (int i = 0; i < 10; ++i) {
    TrackedFrame f = trackedAtZ(0.1 * i);
    f.depth = cv::Mat(24, 32, CV_32FC1, cv::Scalar(depth_at(0.1 * i)));
    f.confidence = cv::Mat(24, 32, CV_32FC1, cv::Scalar(10));
    check.add(f, nullptr, floorBelow(f.camera_to_map.translation(), 0.5));
  }
  return check.finish("uw", false);
}

}  // namespace

// Without the evidence the cluster is in the body at z = 0.5, 0.6, 0.7 (within 0.15 of
// z = 0.6): 40 >= N_occ 30 at consecutive samples, a collision. Frames reading 10
// everywhere saw past it: the views (16 x 12 after the shrink, fx = 8) at z = 0 .. 0.5
// see each point 0.6 - z ahead, and at least those at z = 0, 0.1, 0.2 hold every point
// inside the image (row 8 * 0.245 / 0.4 + 6 = 10.9 < 12 at z = 0.2), 10 > 1.3 * 0.6:
// at least 3 frames through, none in support, so all 40 are left out at 2.
TEST(FreeSpaceEvidence, PointsTheBranchSawPastAreNoObstacle) {
  const auto far = [](double) { return 10.0; };
  const BranchVerdict off = walkToward(seeThroughConfig(0), far);
  EXPECT_TRUE(off.collision_pc);
  EXPECT_EQ(off.occupied_max, 40);
  EXPECT_EQ(off.see_through_points, 0);
  const BranchVerdict on = walkToward(seeThroughConfig(2), far);
  EXPECT_FALSE(on.collision_pc);
  EXPECT_EQ(on.occupied_max, 0);
  EXPECT_EQ(on.see_through_points, 40);
}

// A wall at z = 0.6: each frame before it reads 0.6 - z, which is where the points are
// (support); from z = 0.6 on it is behind the camera (unknown). Nothing is seen
// through and the collision stands.
TEST(FreeSpaceEvidence, PointsTheBranchSawWhereTheyAreStay) {
  const BranchVerdict v = walkToward(seeThroughConfig(2), [](double z) {
    return z < 0.55 ? 0.6 - z : std::numeric_limits<double>::quiet_NaN();
  });
  EXPECT_TRUE(v.collision_pc);
  EXPECT_EQ(v.occupied_max, 40);
  EXPECT_EQ(v.see_through_points, 0);
}
