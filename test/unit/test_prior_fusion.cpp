// The depth prior's fusion with the plane sweep (prior_fusion.h), on hand-worked
// pixels, and the visual SLAM turning in place with a prior: cloud-only views appear
// where triangulation has nothing.
#include <gtest/gtest.h>

#include <cmath>

#include "test_visual_scene.h"
#include "valerant/common/error.h"
#include "valerant/slam/visual/prior_fusion.h"
#include "valerant/slam/visual/visual_slam.h"

using namespace valerant;

namespace {

cv::Mat image(std::initializer_list<float> values) {
  cv::Mat m(1, static_cast<int>(values.size()), CV_32F);
  int i = 0;
  for (float v : values) m.at<float>(0, i++) = v;
  return m;
}

const float kNaN = std::nanf("");

}  // namespace

TEST(PriorFusion, ScaleIsTheMedianRatioOverConfidentSweepPixels) {
  PriorFusionParams p;
  p.min_scale_pixels = 3;
  // Ratios 2, 2.5, 3 on confident pixels; the unconfident (ratio 10), unknown and
  // too far (45 m > 40) pixels do not count. Median: 2.5.
  const cv::Mat sweep = image({2, 5, 9, 10, kNaN, 90});
  const cv::Mat conf = image({5, 4, 6, 1, 0, 9});
  const cv::Mat prior = image({1, 2, 3, 1, 1, 45});
  const auto scale = visual::priorScale(sweep, conf, prior, p);
  ASSERT_TRUE(scale);
  EXPECT_DOUBLE_EQ(*scale, 2.5);
  p.min_scale_pixels = 4;  // too few pixels: no estimate
  EXPECT_FALSE(visual::priorScale(sweep, conf, prior, p));
}

TEST(PriorFusion, TriangulatedPointsTakeTheirScaleFromThePriorAtTheirPixels) {
  const PriorFusionParams p;  // 40 m
  // Prior (metres) along one row; points at pixels 0..5 with depths in two-view units.
  // Ratios prior / depth: 4/2 = 2, 6/2 = 3, 9/3 = 3, 10/2 = 5; pixel 4's prior (45 m)
  // is beyond 40, pixel 5's point has depth 0, and (7, 0) is outside the image. Median
  // of {2, 3, 3, 5} (the upper middle, as priorScale): 3.
  const cv::Mat prior = image({4, 6, 9, 10, 45, 8});
  const std::vector<cv::Point2f> pixels = {{0, 0}, {1.2f, 0}, {2, 0.4f}, {3, 0}, {4, 0}, {5, 0}, {7, 0}};
  const std::vector<double> depths = {2, 2, 3, 2, 1, 0, 1};
  const auto metres = visual::priorMetresPerUnit(pixels, depths, prior, p, 4);
  ASSERT_TRUE(metres);
  EXPECT_DOUBLE_EQ(*metres, 3.0);
  EXPECT_FALSE(visual::priorMetresPerUnit(pixels, depths, prior, p, 5));  // only 4 usable points
  EXPECT_THROW(visual::priorMetresPerUnit(pixels, {1.0}, prior, p, 1), InputError);
}

TEST(PriorFusion, TheMoreConfidentEstimateWinsPerPixel) {
  const PriorFusionParams p;  // gain 0.6, cap 20, 40 m
  // Prior confidence = 0.6 / b: b = 0.15 -> 4, b = 0.1 -> 6, b = 0.01 -> 60, capped at 20.
  cv::Mat depth = image({3, kNaN, 5, kNaN, kNaN});
  cv::Mat conf = image({10, 0, 2, 0, 0});
  const cv::Mat prior = image({1, 2, 3, 50, 1.5f});
  const cv::Mat log_b = image({std::log(0.15f), std::log(0.1f), std::log(0.1f), std::log(0.1f), std::log(0.01f)});
  visual::fusePrior(depth, conf, prior, log_b, 2.0, p);
  EXPECT_FLOAT_EQ(depth.at<float>(0, 0), 3);  // sweep 10 beats prior 4
  EXPECT_FLOAT_EQ(conf.at<float>(0, 0), 10);
  EXPECT_FLOAT_EQ(depth.at<float>(0, 1), 4);  // no sweep: 2 m x 2 map units per metre
  EXPECT_NEAR(conf.at<float>(0, 1), 6, 1e-5);
  EXPECT_FLOAT_EQ(depth.at<float>(0, 2), 6);  // prior 6 beats sweep 2
  EXPECT_NEAR(conf.at<float>(0, 2), 6, 1e-5);
  EXPECT_TRUE(std::isnan(depth.at<float>(0, 3)));  // 50 m: beyond 40, sky-like
  EXPECT_FLOAT_EQ(conf.at<float>(0, 3), 0);
  EXPECT_FLOAT_EQ(depth.at<float>(0, 4), 3);
  EXPECT_FLOAT_EQ(conf.at<float>(0, 4), 20);  // capped
  EXPECT_THROW(visual::fusePrior(depth, conf, prior, log_b, 0.0, p), InputError);
  EXPECT_THROW(visual::fusePrior(depth, conf, image({1}), log_b, 1.0, p), InputError);
}

TEST(PriorFusion, TurningInPlaceWithAPriorMakesCloudOnlyViews) {
  // The test model (learn/make_test_depth_model.py) predicts depth 2 e^R m with
  // ln b = -1: confidence 0.6 e = 1.63 per pixel, under the 4.0 cut for collision, but
  // the views and their clouds exist. A 90 deg turn in 57 frames with a view every
  // 20 deg of turning: frames 0, 13, 26, 39, 52 (20 deg = 12.67 frames).
  const auto prior = std::make_shared<DepthPrior>(std::string(VALERANT_SOURCE_DIR) + "/test/data/depth_prior_linear.onnx",
                                                  cv::Size(128, 96));
  VisualSlam slam(test::BoxRoom::camera(), SlamConfig{}, prior);
  const test::BoxRoom room({-3, -1.6, -3}, {3.5, 1.6, 14});
  std::vector<int> views;
  for (int i = 0; i <= 57; ++i) {
    const auto pose = test::BoxRoom::pose(Eigen::Vector3d(0, 0, 4), 90.0 * i / 57);
    const TrackedFrame f = slam.track(SlamInput{room.render(test::BoxRoom::camera(), pose).rgb, {}});
    if (f.keyframe) views.push_back(i);
    EXPECT_NE(f.state, TrackingState::kLost);
  }
  EXPECT_EQ(views, (std::vector<int>{0, 13, 26, 39, 52}));
  ASSERT_EQ(slam.keyframeCount(), 5);
  const auto clouds = slam.keyframeClouds();
  EXPECT_EQ(clouds[1].frame, 13);
  EXPECT_FALSE(clouds[1].points.empty());
  // Without a prior the same turn makes none (TurningInPlaceIsRotationOnly).
}
