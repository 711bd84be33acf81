// The visual SLAM backend end to end on a synthetic textured room: forward motion is
// tracked with small drift and dense depth, turning in place is rotation only, branches
// and snapshots are isolated and deterministic across threads, and black or noise
// frames are reported lost instead of throwing.
#include <gtest/gtest.h>

#include <thread>

#include "test_visual_scene.h"
#include "valerant/common/error.h"
#include "valerant/eval/trajectory_metrics.h"
#include "valerant/slam/visual/visual_slam.h"

using namespace valerant;

namespace {

const test::BoxRoom& room() {
  static const test::BoxRoom r({-3, -1.6, -3}, {3.5, 1.6, 14});
  return r;
}

// A camera that starts at the origin and applies `steps` of (forward metres, yaw deg).
struct Sequence {
  std::vector<Eigen::Isometry3d> poses;
  std::vector<test::RenderedView> views;
};

Sequence sequence(const std::vector<std::pair<double, double>>& steps, Eigen::Vector3d start = Eigen::Vector3d::Zero(),
                  double yaw = 0) {
  Sequence s;
  Eigen::Vector3d c = start;
  auto add = [&] {
    s.poses.push_back(test::BoxRoom::pose(c, yaw));
    s.views.push_back(room().render(test::BoxRoom::camera(), s.poses.back()));
  };
  add();
  for (const auto& [forward, turn] : steps) {
    yaw += turn;
    c += forward * Eigen::Vector3d(std::sin(yaw * M_PI / 180), 0, std::cos(yaw * M_PI / 180));
    add();
  }
  return s;
}

std::vector<std::pair<double, double>> repeat(int n, double forward, double yaw) {
  return std::vector<std::pair<double, double>>(n, {forward, yaw});
}

const Sequence& forwardRun() {  // the "uw" candidate: 57 frames, 8 m
  static const Sequence s = sequence(repeat(57, 8.0 / 57, 0));
  return s;
}

TrackedFrame feed(Slam& slam, const cv::Mat& rgb) {
  SlamInput in;
  in.rgb = rgb;
  return slam.track(in);
}

std::vector<TrackedFrame> feedAll(Slam& slam, const Sequence& s, size_t from = 0, size_t to = SIZE_MAX) {
  std::vector<TrackedFrame> out;
  for (size_t i = from; i < std::min(to, s.views.size()); ++i) out.push_back(feed(slam, s.views[i].rgb));
  return out;
}

bool samePoses(const std::vector<Eigen::Isometry3d>& a, const std::vector<Eigen::Isometry3d>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].matrix() != b[i].matrix()) return false;
  return true;
}

VisualSlam makeSlam() { return VisualSlam(test::BoxRoom::camera(), SlamConfig{}); }

}  // namespace

TEST(VisualSlam, ForwardMotionHasSmallDriftAndDenseDepth) {
  VisualSlam slam = makeSlam();
  const Sequence& s = forwardRun();
  const auto frames = feedAll(slam, s);
  int tracking = 0;
  for (const auto& f : frames) {
    EXPECT_NE(f.state, TrackingState::kLost);
    tracking += f.state == TrackingState::kTracking;
  }
  EXPECT_GT(tracking, 45);
  EXPECT_GE(slam.keyframeCount(), 5);
  const TrajectoryError e = trajectoryError(slam.trajectory(), s.poses);
  EXPECT_LT(e.ate_percent, 2.0) << "ATE " << e.ate_rmse << " m over " << e.path_length << " m";

  std::vector<cv::Mat> depth, confidence, truth;
  for (size_t i = 0; i < frames.size(); ++i) {
    depth.push_back(frames[i].depth);
    confidence.push_back(frames[i].confidence);
    truth.push_back(s.views[i].depth);
  }
  const DepthError d = depthError(depth, confidence, truth, 4.0);
  EXPECT_LT(d.abs_rel, 0.1);
  EXPECT_GT(d.confident_fraction, 0.2);
  const auto clouds = slam.keyframeClouds();
  ASSERT_EQ(static_cast<int>(clouds.size()), slam.keyframeCount());
  EXPECT_FALSE(clouds.back().points.empty());
}

TEST(VisualSlam, TurningInPlaceIsRotationOnly) {
  VisualSlam slam = makeSlam();
  const Sequence s = sequence(repeat(57, 0, 90.0 / 57), Eigen::Vector3d(0, 0, 4));
  const auto frames = feedAll(slam, s);
  for (size_t i = 1; i < frames.size(); ++i) {
    EXPECT_NE(frames[i].state, TrackingState::kLost) << "frame " << i;
    EXPECT_TRUE(frames[i].rotation_only) << "frame " << i;
  }
  EXPECT_EQ(slam.keyframeCount(), 0);  // nothing triangulated from a turn in place
  const TrajectoryError e = trajectoryError(slam.trajectory(), s.poses);
  EXPECT_LT(e.rotation_rmse_deg, 1.0);
  EXPECT_LT(e.ate_rmse, 1e-9);
}

TEST(VisualSlam, TurnAfterForwardKeepsTheMap) {
  VisualSlam slam = makeSlam();
  auto steps = repeat(30, 0.14, 0);
  const auto turn = repeat(40, 0, 90.0 / 57);
  steps.insert(steps.end(), turn.begin(), turn.end());
  const Sequence s = sequence(steps);
  const auto frames = feedAll(slam, s);
  const int keyframes_after_forward = slam.keyframeCount();
  for (size_t i = 31; i < frames.size(); ++i) {
    EXPECT_NE(frames[i].state, TrackingState::kLost) << "frame " << i;
    EXPECT_TRUE(frames[i].rotation_only) << "frame " << i;
    EXPECT_FALSE(frames[i].keyframe) << "frame " << i;
  }
  EXPECT_EQ(slam.keyframeCount(), keyframes_after_forward);
  const TrajectoryError e = trajectoryError(slam.trajectory(), s.poses);
  EXPECT_LT(e.rotation_rmse_deg, 1.5);
  EXPECT_LT(e.ate_percent, 2.0);
}

TEST(VisualSlam, SnapshotsAndBranchesAreIsolated) {
  VisualSlam base = makeSlam();
  const Sequence& s = forwardRun();
  feedAll(base, s, 0, 25);
  const auto saved = base.snapshot();
  const auto base_poses = base.trajectory();
  const int base_keyframes = base.keyframeCount();

  auto a = base.branch();
  auto b = base.branch();
  feedAll(*a, s, 25, 45);
  // A's frames change neither B nor the base.
  EXPECT_TRUE(samePoses(b->trajectory(), base_poses));
  EXPECT_EQ(b->keyframeCount(), base_keyframes);
  EXPECT_GT(a->keyframeCount(), base_keyframes);
  const Sequence turn = sequence(repeat(20, 0, 2.0), s.poses[24].translation());
  feedAll(*b, turn, 1);
  EXPECT_EQ(a->trajectory().size(), 45u);

  // Restoring A returns it to the snapshot, and replaying gives the same result.
  const auto a_poses = a->trajectory();
  a->restore(saved);
  EXPECT_TRUE(samePoses(a->trajectory(), base_poses));
  EXPECT_EQ(a->keyframeCount(), base_keyframes);
  feedAll(*a, s, 25, 45);
  EXPECT_TRUE(samePoses(a->trajectory(), a_poses));
}

TEST(VisualSlam, FiveBranchesOnFiveThreadsAgree) {
  VisualSlam base = makeSlam();
  const Sequence& s = forwardRun();
  feedAll(base, s, 0, 20);
  std::vector<std::unique_ptr<Slam>> branches;
  for (int i = 0; i < 5; ++i) branches.push_back(base.branch());
  std::vector<std::thread> threads;
  for (auto& b : branches) threads.emplace_back([&s, &b] { feedAll(*b, s, 20, 45); });
  for (auto& t : threads) t.join();
  for (int i = 1; i < 5; ++i) {
    EXPECT_TRUE(samePoses(branches[i]->trajectory(), branches[0]->trajectory())) << "branch " << i;
    EXPECT_EQ(branches[i]->keyframeCount(), branches[0]->keyframeCount());
  }
}

TEST(VisualSlam, BlackAndNoiseFramesAreLost) {
  VisualSlam slam = makeSlam();
  const cv::Mat black(240, 320, CV_8UC3, cv::Scalar(0, 0, 0));
  EXPECT_EQ(feed(slam, black).state, TrackingState::kLost);  // nothing to start from
  const Sequence& s = forwardRun();
  feedAll(slam, s, 0, 20);
  const Eigen::Isometry3d last = slam.trajectory().back();
  for (int i = 0; i < 3; ++i) {
    const TrackedFrame f = feed(slam, black);
    EXPECT_EQ(f.state, TrackingState::kLost);
    EXPECT_TRUE(f.camera_to_map.isApprox(last));
  }
  cv::Mat noise(240, 320, CV_8UC3);
  cv::RNG rng(3);
  for (int i = 0; i < 3; ++i) {
    rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
    EXPECT_EQ(feed(slam, noise).state, TrackingState::kLost) << "noise frame " << i;
  }
  EXPECT_EQ(slam.trajectory().size(), 27u);
}

TEST(VisualSlam, RejectsFramesOfTheWrongKind) {
  VisualSlam slam = makeSlam();
  EXPECT_THROW(feed(slam, cv::Mat(240, 320, CV_8UC1, cv::Scalar(0))), InputError);
  EXPECT_THROW(feed(slam, cv::Mat(120, 160, CV_8UC3, cv::Scalar(0))), InputError);
  EXPECT_THROW(slam.restore(std::make_shared<SlamState>()), InputError);
}
