// Oracle SLAM: ground truth converted to metres, keyframes on schedule, branches
// isolated, a NaN pose reported as lost instead of poisoning the map.
#include <gtest/gtest.h>

#include <limits>

#include "valerant/common/error.h"
#include "valerant/slam/oracle_slam.h"
#include "valerant/slam/rollout_truth.h"

using namespace valerant;

namespace {

const CameraIntrinsics kCamera = CameraIntrinsics::fromHorizontalFov(32, 24, 90);  // fx = 16

// A camera at x = `x_units` looking along +X at a wall 2 m ahead.
FrameTruth truthAt(double x_units) {
  FrameTruth t;
  t.camera_to_world.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;  // optical axes in the BSP frame
  t.camera_to_world.translation() = Eigen::Vector3d(x_units, 0, 50);
  t.depth_m = cv::Mat(24, 32, CV_32F, cv::Scalar(2.0f));
  return t;
}

// Feeds the oracle frames of rollout 1 as a pipeline does: each frame's truth is held
// in the source while it is tracked.
struct Feeder {
  std::shared_ptr<RolloutTruth> truth = std::make_shared<RolloutTruth>();
  int frames = 0;

  TrackedFrame operator()(Slam& slam, const FrameTruth& frame_truth) {
    const FrameStamp stamp{1, frames++};
    const RolloutTruth::Hold held = truth->hold(stamp, frame_truth);
    return slam.track(SlamInput{cv::Mat(24, 32, CV_8UC3, cv::Scalar(10, 20, 30)), stamp});
  }
};

}  // namespace

TEST(OracleSlam, PosesInMetresAndBackProjectedPoints) {
  SlamConfig config;
  Feeder feed;
  OracleSlam slam(kCamera, config, feed.truth);
  const TrackedFrame f = feed(slam, truthAt(64));
  EXPECT_EQ(f.state, TrackingState::kTracking);
  EXPECT_TRUE(f.keyframe);
  EXPECT_TRUE(f.camera_to_map.translation().isApprox(Eigen::Vector3d(2, 0, 50.0 / 32)));
  EXPECT_FLOAT_EQ(f.confidence.at<float>(5, 5), 10.f);
  const auto clouds = slam.keyframeClouds();
  ASSERT_EQ(clouds.size(), 1u);
  // stride 4 over 32x24: 8 x 6 pixels, all on the wall at x = 2 + 2 = 4 m.
  ASSERT_EQ(clouds[0].points.size(), 48u);
  for (const auto& p : clouds[0].points) EXPECT_NEAR(p.position.x(), 4.0, 1e-5);
  // Pixel (u=2, v=2): ray ((2-16)/16, (2-12)/16, 1) * 2 m -> right = -1.75, down = -1.25.
  const CloudPoint& first = clouds[0].points[0];
  EXPECT_NEAR(first.position.y(), 1.75, 1e-5);               // right is -Y
  EXPECT_NEAR(first.position.z(), 50.0 / 32 + 1.25, 1e-5);  // down is -Z
  EXPECT_EQ(first.rgb[2], 30);
}

TEST(OracleSlam, KeyframeScheduleAndRotationOnly) {
  SlamConfig config;
  Feeder feed;
  OracleSlam slam(kCamera, config, feed.truth);
  int keyframes = 0;
  for (int i = 0; i < 17; ++i) keyframes += feed(slam, truthAt(i * 4.0)).keyframe;
  EXPECT_EQ(keyframes, 3);  // frames 0, 8, 16
  EXPECT_TRUE(feed(slam, truthAt(16 * 4.0)).rotation_only);
  EXPECT_EQ(slam.trajectory().size(), 18u);
}

TEST(OracleSlam, BranchesAndSnapshotsAreIsolated) {
  SlamConfig config;
  Feeder feed;
  OracleSlam base(kCamera, config, feed.truth);
  feed(base, truthAt(0));
  const auto saved = base.snapshot();
  auto a = base.branch();
  auto b = base.branch();
  for (int i = 1; i <= 9; ++i) feed(*a, truthAt(i * 10.0));
  EXPECT_EQ(a->keyframeCount(), 2);
  EXPECT_EQ(b->keyframeCount(), 1);
  EXPECT_EQ(b->trajectory().size(), 1u);
  a->restore(saved);
  EXPECT_EQ(a->keyframeCount(), 1);
  EXPECT_EQ(a->trajectory().size(), 1u);
}

TEST(OracleSlam, NanPoseIsLostAndMissingTruthIsAnError) {
  SlamConfig config;
  Feeder feed;
  OracleSlam slam(kCamera, config, feed.truth);
  feed(slam, truthAt(0));
  FrameTruth bad = truthAt(8);
  bad.camera_to_world.translation().x() = std::numeric_limits<double>::quiet_NaN();
  const TrackedFrame f = feed(slam, bad);
  EXPECT_EQ(f.state, TrackingState::kLost);
  EXPECT_TRUE(f.camera_to_map.matrix().allFinite());
  EXPECT_EQ(slam.keyframeCount(), 1);
  // A frame the source holds no truth for (released, or never held) is an error, and
  // so is an oracle without a source.
  EXPECT_THROW(slam.track(SlamInput{cv::Mat(24, 32, CV_8UC3), {1, 0}}), InputError);
  EXPECT_THROW(OracleSlam(kCamera, config, nullptr), InputError);
}

TEST(RolloutTruth, HoldsARolloutsFramesUntilTheLastHoldEnds) {
  Rollout rollout;
  rollout.id = 5;
  rollout.frames.assign(2, cv::Mat(24, 32, CV_8UC3));
  rollout.truth = {truthAt(32), truthAt(64)};
  const auto truth = std::make_shared<RolloutTruth>();
  EXPECT_FALSE(truth->viewOf({5, 1}));
  {
    const RolloutTruth::Hold held = truth->hold(rollout);
    const auto view = truth->viewOf({5, 1});
    ASSERT_TRUE(view);
    EXPECT_DOUBLE_EQ(view->camera_to_world.translation().x(), 64);
    EXPECT_EQ(view->depth_m.data, rollout.truth[1].depth_m.data);  // shared, not copied
    EXPECT_FALSE(truth->viewOf({5, 2}));
    EXPECT_FALSE(truth->viewOf({4, 1}));
    {
      // The same frame held twice (committed SLAM and a branch) stays until both end.
      const RolloutTruth::Hold again = truth->hold({5, 0}, rollout.truth[0]);
    }
    EXPECT_TRUE(truth->viewOf({5, 0}));
  }
  EXPECT_FALSE(truth->viewOf({5, 0}));
  EXPECT_FALSE(truth->viewOf({5, 1}));
  Rollout without_truth = rollout;
  without_truth.truth.clear();
  const RolloutTruth::Hold nothing = truth->hold(without_truth);
  EXPECT_FALSE(truth->viewOf({5, 0}));
}
