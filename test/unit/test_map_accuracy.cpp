// Map accuracy and completeness on a hand-made floor: samples every 0.1 m on a 2 m x
// 2 m square at z = 0, a camera 1 m above looking straight down.
#include <gtest/gtest.h>

#include <random>

#include "valerant/eval/map_accuracy.h"

using namespace valerant;

namespace {

constexpr double kUnits = 32.0;

std::vector<quake3::SurfaceSample> floorSamples() {
  std::vector<quake3::SurfaceSample> s;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j)
      s.push_back({Eigen::Vector3f(-1 + 0.1 * i, -1 + 0.1 * j, 0) * kUnits, Eigen::Vector3f::UnitZ()});
  return s;
}

// Looking down from 1 m: the 90-degree camera sees a 2 m x 2 m patch; truth depth 1 m.
FrameTruth downCamera(const CameraIntrinsics& k) {
  FrameTruth f;
  f.camera_to_world.linear() << 0, -1, 0, -1, 0, 0, 0, 0, -1;
  f.camera_to_world.translation() = Eigen::Vector3d(0, 0, 1) * kUnits;
  f.depth_m = cv::Mat(k.height, k.width, CV_32F, cv::Scalar(1.0f));
  return f;
}

}  // namespace

TEST(MapAccuracy, DistancesToTheSurface) {
  const CameraIntrinsics k = CameraIntrinsics::fromHorizontalFov(64, 64, 90);
  // Straight above samples: 30 points 0.1 m up and 10 points 0.3 m up, so the median
  // is 0.1 and the 90th percentile (index 36 of 40) is 0.3.
  std::vector<Eigen::Vector3d> map;
  for (int i = 0; i < 30; ++i) map.push_back({-1 + 0.1 * (i % 21), -1 + 0.1 * (i / 21), 0.1});
  for (int i = 0; i < 10; ++i) map.push_back({-1 + 0.1 * i, 0.5, 0.3});
  const MapAccuracy a = mapAccuracy(map, floorSamples(), {downCamera(k)}, k);
  EXPECT_EQ(a.map_points, 40);
  EXPECT_NEAR(a.median_m, 0.1, 1e-6);
  EXPECT_NEAR(a.p90_m, 0.3, 1e-6);
}

TEST(MapAccuracy, CompletenessOfWhatTheCameraSaw) {
  const CameraIntrinsics k = CameraIntrinsics::fromHorizontalFov(64, 64, 90);
  // Map points cover x < 0 of the floor exactly.
  std::vector<Eigen::Vector3d> map;
  for (const auto& s : floorSamples())
    if (s.position.x() < -1e-3) map.push_back(s.position.cast<double>() / kUnits);
  const MapAccuracy a = mapAccuracy(map, floorSamples(), {downCamera(k)}, k);
  // fx = 32: pixel u sees camera x = (u - 32) / 32 in [-1, 0.97]. Camera x is world -Y
  // and camera y world -X, so world x and y in [-0.97, 1]: samples -0.9 .. 1.0, 20 x 20.
  EXPECT_EQ(a.seen_samples, 400);
  // Covered within 0.25 m of the map (x <= -0.1): x = -0.9 .. 0.1, 11 of 20 columns.
  EXPECT_DOUBLE_EQ(a.completeness_percent, 100.0 * 11 / 20);
  // Nothing seen, nothing complete; an empty map is 0%.
  const MapAccuracy empty = mapAccuracy({}, floorSamples(), {downCamera(k)}, k);
  EXPECT_EQ(empty.completeness_percent, 0.0);
}

// A frame tests only the samples within its reach (map_accuracy.cpp): the largest
// truth depth (1 m) / 0.95 times the corner ray (sqrt(1 + 2 (32.5/32)^2) = 1.75 per metre
// of depth), 1.86 m here. The floor's corner samples (1.73 m away) are still seen; a
// patch 100 m away, and samples 5 m under the floor (farther than the truth depth, so
// hidden) are not.
TEST(MapAccuracy, SamplesBeyondAFramesReachAreNotSeen) {
  const CameraIntrinsics k = CameraIntrinsics::fromHorizontalFov(64, 64, 90);
  std::vector<quake3::SurfaceSample> samples = floorSamples();
  for (const auto& s : floorSamples()) {
    samples.push_back({s.position + Eigen::Vector3f(100, 0, 0) * kUnits, Eigen::Vector3f::UnitZ()});
    samples.push_back({s.position + Eigen::Vector3f(0, 0, -5) * kUnits, Eigen::Vector3f::UnitZ()});
  }
  std::vector<Eigen::Vector3d> map;
  for (const auto& s : floorSamples()) map.push_back(s.position.cast<double>() / kUnits);
  const MapAccuracy a = mapAccuracy(map, samples, {downCamera(k)}, k);
  EXPECT_EQ(a.seen_samples, 400);  // the 20 x 20 of CompletenessOfWhatTheCameraSaw
  EXPECT_DOUBLE_EQ(a.completeness_percent, 100.0);
}

// Truth poses without depth (what the graph's explorer has): completeness is not
// measured (NaN), while accuracy still is.
TEST(MapAccuracy, CompletenessNeedsDepthTruth) {
  const CameraIntrinsics k = CameraIntrinsics::fromHorizontalFov(64, 64, 90);
  FrameTruth pose_only = downCamera(k);
  pose_only.depth_m = cv::Mat();
  const MapAccuracy a = mapAccuracy({{0, 0, 0.1}}, floorSamples(), {pose_only}, k);
  EXPECT_TRUE(std::isnan(a.completeness_percent));
  EXPECT_EQ(a.seen_samples, 0);
  EXPECT_NEAR(a.median_m, 0.1, 1e-6);
}

// Each frame skips the 4 m cells wholly behind it or beside its view (map_accuracy.cpp);
// the seen samples must be exactly those of testing every sample. A tilted camera with a
// flat truth depth of 6 m and samples all around it, many on the 6 m plane, some just
// inside and outside the image's edges.
TEST(MapAccuracy, CellsOutsideTheViewHideNoSeenSample) {
  const CameraIntrinsics k = CameraIntrinsics::fromHorizontalFov(80, 60, 90);
  FrameTruth frame;
  frame.camera_to_world.linear() =
      (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(-1.9, Eigen::Vector3d::UnitX())).matrix();
  frame.camera_to_world.translation() = Eigen::Vector3d(3, -2, 1.5) * kUnits;
  frame.depth_m = cv::Mat(k.height, k.width, CV_32F, cv::Scalar(6.0f));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> anywhere(-30, 30), unit(0, 1);
  std::vector<quake3::SurfaceSample> samples;
  const Eigen::Isometry3d& pose = frame.camera_to_world;
  for (int i = 0; i < 20000; ++i) {
    Eigen::Vector3d metres;
    if (i % 2 == 0) {
      metres = Eigen::Vector3d(anywhere(rng), anywhere(rng), anywhere(rng)) + pose.translation() / kUnits;
    } else {  // on the 6 m plane, over the image and half a pixel to 10 pixels past it
      const double u = -10 + (k.width + 20) * unit(rng), v = -10 + (k.height + 20) * unit(rng);
      const Eigen::Vector3d ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1);
      metres = (pose * (6.0 * ray * kUnits)) / kUnits;
    }
    samples.push_back({(metres * kUnits).cast<float>(), Eigen::Vector3f::UnitZ()});
  }
  int expected = 0;  // every sample tested, as mapAccuracy does it per sample
  const Eigen::Isometry3d world_to_camera = pose.inverse();
  for (const auto& s : samples) {
    const Eigen::Vector3d m = s.position.cast<double>() / kUnits;
    const Eigen::Vector3d c = world_to_camera * (m * kUnits) / kUnits;
    if (c.z() <= 0) continue;
    const long u = std::lround(k.fx * c.x() / c.z() + k.cx), v = std::lround(k.fy * c.y() / c.z() + k.cy);
    if (u < 0 || v < 0 || u >= k.width || v >= k.height) continue;
    expected += std::abs(6.0 - c.z()) <= 0.05 * c.z();
  }
  ASSERT_GT(expected, 1000);
  MapAccuracyParams params;
  params.frame_stride = 1;
  EXPECT_EQ(mapAccuracy({{0, 0, 0}}, samples, {frame}, k, params).seen_samples, expected);
}
