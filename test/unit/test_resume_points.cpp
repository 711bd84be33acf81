// A candidate that begins with the frames of an earlier one of the same step continues
// from that one's kept branch (resume_points.h): the result must be the one tracking
// its frames from the committed state gives, and nothing may resume from frames that
// differ. On a real map with the oracle SLAM at a small resolution, as test_episode.
#include <gtest/gtest.h>

#include "openarena_data.h"
#include "valerant/explore/local_branch_pipeline.h"
#include "valerant/explore/resume_points.h"
#include "valerant/slam/slam_factory.h"
#include "valerant/world/quake3/quake3_world.h"

using namespace valerant;

namespace {

Config smallConfig() {
  Config c;
  c.world.width = 96;
  c.world.height = 72;
  c.slam.backend = "oracle";
  c.slam.cloud_stride_px = 1;  // RF's 300 floor inliers at 96x72 (test_episode.cpp)
  return c;
}

void expectSameBranch(const BranchResult& a, const BranchResult& b) {
  ASSERT_EQ(a.poses.size(), b.poses.size());
  for (size_t i = 0; i < a.poses.size(); ++i) EXPECT_TRUE(a.poses[i].isApprox(b.poses[i], 0)) << "frame " << i;
  ASSERT_EQ(a.keyframes.size(), b.keyframes.size());
  for (size_t k = 0; k < a.keyframes.size(); ++k) {
    EXPECT_EQ(a.keyframes[k].frame, b.keyframes[k].frame);
    EXPECT_EQ(a.keyframes[k].points.size(), b.keyframes[k].points.size());
    EXPECT_EQ(a.keyframe_floors[k].known, b.keyframe_floors[k].known);
  }
  EXPECT_EQ(a.floor_reliable, b.floor_reliable);
  const BranchVerdict &x = a.verdict, &y = b.verdict;
  EXPECT_EQ(x.candidate, y.candidate);
  EXPECT_EQ(x.collision_pc, y.collision_pc);
  EXPECT_EQ(x.collision_depth, y.collision_depth);
  EXPECT_EQ(x.occupied_max, y.occupied_max);
  EXPECT_EQ(x.min_near_ratio, y.min_near_ratio);
  EXPECT_EQ(x.slam_lost, y.slam_lost);
  EXPECT_EQ(x.floor_unknown, y.floor_unknown);
  EXPECT_EQ(x.prefix_frames, y.prefix_frames);
}

}  // namespace

TEST(ResumePoints, AShortTranslationResumesFromItsCandidateAsIfTrackedAgain) {
  VALERANT_REQUIRE_OPENARENA();
  const Config config = smallConfig();
  auto map = quake3::loadQuake3Map("oa_dm1", config.world.patch_level);
  quake3::Quake3World world(map, config);
  const ActionSequence uw = makeActionSequence("uw", config), uw32 = makeActionSequence("uw@32", config);
  const ActionSequence jq = makeActionSequence("jq", config), jq80 = makeActionSequence("jq:80", config);

  LocalBranchPipeline resuming(world.intrinsics(), config);
  resuming.start(world.context());
  resuming.evaluate(world.rollout(uw), false, {sharedFrames(uw, uw32)}).get();
  resuming.evaluate(world.rollout(jq), true, {sharedFrames(jq, jq80)}).get();
  const BranchResult short_resumed = resuming.evaluate(world.rollout(uw32), false, {}).get();
  const BranchResult long_resumed = resuming.evaluate(world.rollout(jq80), true, {}).get();

  LocalBranchPipeline fresh(world.intrinsics(), config);
  fresh.start(world.context());
  const BranchResult short_fresh = fresh.evaluate(world.rollout(uw32), false, {}).get();
  const BranchResult long_fresh = fresh.evaluate(world.rollout(jq80), true, {}).get();

  // The short one tracked no frame of its own; the long turn only its last 23.
  EXPECT_EQ(short_resumed.seconds.slam, 0.0);
  EXPECT_GT(short_fresh.seconds.slam, 0.0);
  EXPECT_EQ(short_resumed.poses.size(), 32u);
  expectSameBranch(short_resumed, short_fresh);
  expectSameBranch(long_resumed, long_fresh);
  EXPECT_FALSE(short_resumed.keyframes.empty());

  // Committing the resumed branch adopts its SLAM, and the kept runs are dropped: the
  // next step's uw@32 (from another place) tracks its own frames.
  world.commit(short_resumed.rollout);
  resuming.commit(short_resumed);
  EXPECT_GT(resuming.evaluate(world.rollout(uw32), false, {}).get().seconds.slam, 0.0);
}

TEST(ResumePoints, OnlyTheSameFramesResume) {
  VALERANT_REQUIRE_OPENARENA();
  const Config config = smallConfig();
  auto map = quake3::loadQuake3Map("oa_dm1", config.world.patch_level);
  quake3::Quake3World world(map, config);
  auto truth = std::make_shared<RolloutTruth>();
  auto slam = makeSlam("oracle", world.intrinsics(), config, truth);
  const Rollout uw = world.rollout(makeActionSequence("uw", config));
  const RolloutTruth::Hold held = truth->hold(uw);
  BranchRun run(slam->branch(), FloorEstimator(config.floor, Eigen::Vector3d::UnitY(), 4.0, 0), {}, config);
  for (size_t i = 0; i < 10; ++i) run.track(uw.frames[i], uw.id);

  ResumePoints points;
  points.keep(uw, run.fork());
  points.keep(uw, std::move(run));  // the same ten frames twice: either serves
  ASSERT_EQ(points.size(), 2u);

  Rollout same = uw;  // the same frames (other images of equal bytes)
  for (cv::Mat& f : same.frames) f = f.clone();
  const auto resumed = points.longestPrefixOf(same);
  ASSERT_TRUE(resumed.has_value());
  EXPECT_EQ(resumed->frames(), 10u);

  Rollout shorter = uw;
  shorter.frames.resize(9);
  shorter.truth.resize(9);
  EXPECT_FALSE(points.longestPrefixOf(shorter).has_value());

  Rollout changed = same;
  changed.frames[9] = changed.frames[9].clone();
  changed.frames[9].at<cv::Vec3b>(0, 0)[0] ^= 1;  // one bit of the tenth frame
  EXPECT_FALSE(points.longestPrefixOf(changed).has_value());

  Rollout moved = uw;
  moved.truth[3].camera_to_world.translation().x() += 1e-9;  // equal images, another pose
  EXPECT_FALSE(points.longestPrefixOf(moved).has_value());

  Rollout without_truth = uw;
  without_truth.truth.clear();
  EXPECT_FALSE(points.longestPrefixOf(without_truth).has_value());

  points.clear();
  EXPECT_FALSE(points.longestPrefixOf(same).has_value());
}
