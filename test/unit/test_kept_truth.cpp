// What an episode keeps of its frames' ground truth: no candidate depth, committed depth
// every kCommittedDepthStride-th frame of the trajectory (the frames map accuracy reads).
#include <gtest/gtest.h>

#include "valerant/eval/map_accuracy.h"
#include "valerant/explore/kept_truth.h"

using namespace valerant;

namespace {

std::vector<FrameTruth> framesWithDepth(int n) {
  std::vector<FrameTruth> frames(n);
  for (int i = 0; i < n; ++i) {
    frames[i].depth_m = cv::Mat(2, 2, CV_32F, cv::Scalar(i));
    frames[i].in_solid = i % 2;
    frames[i].camera_to_world = Eigen::Translation3d(i, 0, 0) * Eigen::Isometry3d::Identity();
  }
  return frames;
}

}  // namespace

TEST(KeptTruth, CandidatesKeepPosesAndFlagsButNoDepth) {
  const auto frames = framesWithDepth(3);
  const auto kept = withoutDepth(frames);
  ASSERT_EQ(kept.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(kept[i].depth_m.empty());
    EXPECT_EQ(kept[i].in_solid, frames[i].in_solid);
    EXPECT_DOUBLE_EQ(kept[i].camera_to_world.translation().x(), i);
    EXPECT_FALSE(frames[i].depth_m.empty());  // the rollout's own frames are untouched
  }
}

TEST(KeptTruth, CommittedFramesKeepDepthAtTheStrideOfTheWholeTrajectory) {
  ASSERT_EQ(kCommittedDepthStride, 8u);
  EXPECT_EQ(MapAccuracyParams{}.frame_stride, 8);  // the frames map accuracy tests
  // 5 context frames, then a step of 10: trajectory indices 0..14 keep depth at 0 and 8.
  std::vector<FrameTruth> committed;
  appendCommittedTruth(committed, framesWithDepth(5));
  appendCommittedTruth(committed, framesWithDepth(10));
  ASSERT_EQ(committed.size(), 15u);
  for (size_t i = 0; i < committed.size(); ++i) EXPECT_EQ(!committed[i].depth_m.empty(), i == 0 || i == 8) << i;
  EXPECT_EQ(committed[8].depth_m.at<float>(0, 0), 3.f);  // the step's 4th frame (index 3)
  // A rewind truncates; appending again goes on from the kept length: 6 + 4 keeps 8.
  committed.resize(6);
  appendCommittedTruth(committed, framesWithDepth(4));
  EXPECT_FALSE(committed[8].depth_m.empty());
  EXPECT_TRUE(committed[9].depth_m.empty());
}
