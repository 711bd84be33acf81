// Geometry blocks of the visual SLAM on synthetic points with a known answer:
// two-view initialisation, PnP, the rotation model and local bundle adjustment.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "valerant/slam/visual/local_bundle_adjustment.h"
#include "valerant/slam/visual/pinhole.h"
#include "valerant/slam/visual/pnp_tracker.h"
#include "valerant/slam/visual/rotation_model.h"
#include "valerant/slam/visual/two_view_initializer.h"

using namespace valerant;
using namespace valerant::visual;

namespace {

const CameraIntrinsics kCamera = CameraIntrinsics::fromHorizontalFov(320, 240, 90);

// Points in front of the identity camera, 2 to 10 units deep, spread over the view.
std::vector<Eigen::Vector3d> scenePoints(int n, uint64_t seed) {
  cv::RNG rng(seed);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < n; ++i) {
    const double z = rng.uniform(2.0, 10.0);
    points.emplace_back(rng.uniform(-0.9, 0.9) * z, rng.uniform(-0.7, 0.7) * z, z);
  }
  return points;
}

std::vector<cv::Point2f> pixels(const std::vector<Eigen::Vector3d>& points, const Eigen::Isometry3d& camera_to_map,
                                double noise_px, uint64_t seed) {
  cv::RNG rng(seed);
  std::vector<cv::Point2f> out;
  for (const auto& p : points) {
    const Eigen::Vector2d px = project(kCamera, camera_to_map.inverse() * p);
    out.emplace_back(static_cast<float>(px.x() + rng.gaussian(noise_px)),
                     static_cast<float>(px.y() + rng.gaussian(noise_px)));
  }
  return out;
}

Eigen::Isometry3d movedCamera() {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(0.1, Eigen::Vector3d(0.2, 1, 0.1).normalized()).toRotationMatrix();
  t.translation() = Eigen::Vector3d(0.5, 0.05, 0.3);
  return t;
}

double angleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180.0 / M_PI;
}

}  // namespace

TEST(VisualTwoView, RecoversPoseAndStructureUpToScale) {
  const auto points = scenePoints(200, 1);
  const Eigen::Isometry3d b_pose = movedCamera();
  cv::setRNGSeed(1);
  const auto result = initializeTwoView(pixels(points, Eigen::Isometry3d::Identity(), 0.1, 2),
                                        pixels(points, b_pose, 0.1, 3), kCamera, TwoViewParams{});
  ASSERT_TRUE(result && result->ready);
  EXPECT_LT(angleDeg(result->b_to_a.linear(), b_pose.linear()), 0.2);
  EXPECT_NEAR(result->b_to_a.translation().norm(), 1.0, 1e-9);
  const double scale = b_pose.translation().norm();
  EXPECT_GT(result->b_to_a.translation().dot(b_pose.translation() / scale), 0.999);
  ASSERT_GT(result->points.size(), 150u);
  // 0.1 px noise over a few degrees of parallax: about a percent of depth per point.
  std::vector<double> errors;
  for (size_t j = 0; j < result->points.size(); ++j) {
    const Eigen::Vector3d& truth = points[result->indices[j]];
    errors.push_back((result->points[j] * scale - truth).norm() / truth.z());
  }
  std::sort(errors.begin(), errors.end());
  EXPECT_LT(errors[errors.size() / 2], 0.02);
  EXPECT_LT(errors[errors.size() * 9 / 10], 0.06);
}

TEST(VisualTwoView, RejectsPureRotation) {
  const auto points = scenePoints(200, 4);
  Eigen::Isometry3d turned = Eigen::Isometry3d::Identity();
  turned.linear() = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  cv::setRNGSeed(1);
  const auto a = pixels(points, Eigen::Isometry3d::Identity(), 0.3, 5), b = pixels(points, turned, 0.3, 6);
  const auto two_view = initializeTwoView(a, b, kCamera, TwoViewParams{});
  EXPECT_TRUE(!two_view || !two_view->ready);
  // ... which the rotation model explains, with no parallax left over.
  const auto rotation = estimateRotation(a, b, kCamera, 1.0, 20);
  ASSERT_TRUE(rotation);
  EXPECT_LT(angleDeg(rotation->b_from_a, turned.linear().transpose()), 0.05);
  EXPECT_LT(rotation->median_parallax_px, 0.6);
}

TEST(VisualRotationModel, TranslationShowsAsParallax) {
  const auto points = scenePoints(200, 7);
  const auto rotation = estimateRotation(pixels(points, Eigen::Isometry3d::Identity(), 0.3, 8),
                                         pixels(points, movedCamera(), 0.3, 9), kCamera, 1.0, 20);
  EXPECT_TRUE(!rotation || rotation->median_parallax_px > 3.0);
}

TEST(VisualPnp, RecoversKnownPoseWithOutliers) {
  const auto points = scenePoints(150, 10);
  const Eigen::Isometry3d pose = movedCamera();
  auto px = pixels(points, pose, 0.3, 11);
  for (int i = 0; i < 30; ++i) px[i] += cv::Point2f(25.f, -18.f);  // 20 % gross outliers
  std::vector<cv::Point3f> object;
  for (const auto& p : points) object.emplace_back(p.cast<float>().x(), p.cast<float>().y(), p.cast<float>().z());
  cv::setRNGSeed(1);
  const auto result = solvePnp(object, px, kCamera, PnpParams{});
  ASSERT_TRUE(result);
  EXPECT_LT((result->camera_to_map.translation() - pose.translation()).norm(), 0.01);
  EXPECT_LT(angleDeg(result->camera_to_map.linear(), pose.linear()), 0.1);
  EXPECT_EQ(std::count_if(result->inliers.begin(), result->inliers.end(), [](int i) { return i < 30; }), 0);
  EXPECT_GT(result->inliers.size(), 110u);
}

TEST(VisualPnp, TooFewPointsIsNoPose) {
  const auto points = scenePoints(8, 12);
  std::vector<cv::Point3f> object;
  for (const auto& p : points) object.emplace_back(p.cast<float>().x(), p.cast<float>().y(), p.cast<float>().z());
  EXPECT_FALSE(solvePnp(object, pixels(points, Eigen::Isometry3d::Identity(), 0, 1), kCamera, PnpParams{}));
}

TEST(VisualBundleAdjustment, RefinesPerturbedPoseAndPoints) {
  const auto truth = scenePoints(120, 13);
  std::vector<Eigen::Isometry3d> cameras(4, Eigen::Isometry3d::Identity());
  for (int c = 1; c < 4; ++c) cameras[c].translation() = Eigen::Vector3d(0.3 * c, 0, 0.2 * c);
  cv::RNG rng(14);
  std::vector<MapPoint> points(truth.size());
  std::map<int, const MapPoint*> by_id;
  for (size_t i = 0; i < truth.size(); ++i) {
    points[i].position = truth[i] + Eigen::Vector3d(rng.gaussian(0.05), rng.gaussian(0.05), rng.gaussian(0.05));
    for (int c = 0; c < 4; ++c) points[i].observations.push_back({c, project(kCamera, cameras[c].inverse() * truth[i])});
    by_id[static_cast<int>(i)] = &points[i];
  }
  points[0].observations[3].px += Eigen::Vector2d(40, 40);  // one gross outlier
  std::map<int, Eigen::Isometry3d> poses;
  for (int c = 0; c < 4; ++c) poses[c] = cameras[c];
  poses[3].translation() += Eigen::Vector3d(0.04, -0.03, 0.02);
  const auto result = localBundleAdjustment(poses, {2, 3}, by_id, kCamera, BundleAdjustmentParams{});
  ASSERT_TRUE(result.poses.count(3));
  EXPECT_LT((result.poses.at(3).translation() - cameras[3].translation()).norm(), 2e-3);
  EXPECT_EQ(result.rejected, std::vector<int>{0});
  double worst = 0;
  for (const auto& [id, p] : result.points) worst = std::max(worst, (p - truth[id]).norm() / truth[id].z());
  EXPECT_LT(worst, 5e-3);  // from 1 % before
}
