// Keyframe clouds of the visual backend keep every plane-sweep depth exactly once,
// whatever the oracle's cloud_stride_px says: the sweep runs at half resolution and is
// upsampled 2x2 by nearest neighbour, so a keyframe with N finite full-resolution
// depths must give N / 4 points (stride 4 would give N / 16 and starve the floor fit).
#include <gtest/gtest.h>

#include "test_visual_scene.h"
#include "valerant/slam/visual/visual_slam.h"

using namespace valerant;

TEST(VisualKeyframeCloud, OnePointPerSweepDepth) {
  const test::BoxRoom room({-3, -1.6, -3}, {3.5, 1.6, 14});
  SlamConfig config;
  config.cloud_stride_px = 4;
  VisualSlam slam(test::BoxRoom::camera(), config);
  std::vector<cv::Mat> depths;
  for (int i = 0; i < 30; ++i) {
    const auto view = room.render(test::BoxRoom::camera(), test::BoxRoom::pose({0, 0, 0.14 * i}, 0));
    SlamInput in;
    in.rgb = view.rgb;
    depths.push_back(slam.track(in).depth);
  }
  const auto clouds = slam.keyframeClouds();
  ASSERT_GE(clouds.size(), 2u);
  const KeyframeCloud& last = clouds.back();
  const cv::Mat& depth = depths.at(last.frame);
  int finite = 0;
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u) finite += std::isfinite(depth.at<float>(v, u)) && depth.at<float>(v, u) > 0;
  ASSERT_GT(finite, 0);
  EXPECT_EQ(finite % 4, 0);
  EXPECT_EQ(static_cast<int>(last.points.size()), finite / 4);
}
