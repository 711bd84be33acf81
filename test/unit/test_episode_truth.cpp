// Ground truth of an episode that never translates: a spawn in a small room on oa_dm4
// where every forward candidate (8 m) walks into a wall, so the agent only rotates.
// Positions cannot fit a Sim(3) then; the first pose and the floor tie the map to the
// world instead. With the oracle SLAM (map units are metres, camera 50/32 m above the
// floor) the tie's scale must come out near 1, and the floor seen while turning
// must count as observed. Full 320x240 frames: smaller keyframe clouds hold too few
// floor points for a reliable floor, and without one nothing is fused or measured.
#include <gtest/gtest.h>

#include "openarena_data.h"
#include "valerant/eval/episode_truth.h"
#include "valerant/slam/oracle_slam.h"
#include "valerant/world/quake3/quake3_world.h"

using namespace valerant;

TEST(EpisodeTruth, RotationOnlyEpisodeIsTiedToTheWorldByTheFloor) {
  VALERANT_REQUIRE_OPENARENA();
  Config config;
  config.world.spawn = 0;
  config.policy.budget_steps = 2;
  config.slam.backend = "oracle";
  config.collision.prefix_commits = false;  // every full translation collides here; a prefix would move
  auto map = quake3::loadQuake3Map("oa_dm4", config.world.patch_level);
  quake3::Quake3World world(map, config);
  Episode episode(world, std::make_unique<OracleSlam>(world.intrinsics(), config.slam), config);
  episode.runUntilDone(nullptr);
  for (const auto& pose : episode.trajectory())  // precondition: rotations in place only
    ASSERT_TRUE(pose.translation().isApprox(episode.trajectory().front().translation(), 1e-9));

  const auto reachable = quake3::floodFillReachableFloor(*map->collision, world.spawnPoints()[0].origin);
  const EpisodeTruth truth = evaluateEpisodeTruth(episode, reachable);
  EXPECT_FALSE(truth.aligned);
  ASSERT_TRUE(truth.floor_aligned);
  // The estimated floor lies within a few centimetres of the true one (RANSAC on the
  // lower envelope of the keyframe clouds): scale 1 within 5%.
  EXPECT_NEAR(truth.alignment_scale, 1.0, 0.05);
  // The oracle map frame is the BSP frame in metres: no rotation, and the first camera
  // lands on its true centre whatever the scale.
  EXPECT_TRUE(truth.map_to_world_metres.rotation.isApprox(Eigen::Matrix3d::Identity(), 1e-9));
  const Eigen::Vector3d first = episode.trajectory().front().translation();
  EXPECT_TRUE(truth.map_to_world_metres.apply(first).isApprox(first, 1e-9));
  EXPECT_GT(truth.observed_reachable_m2, 10.0);
}

namespace {

// A candidate of a hand-made history: one frame per entry of `in_solid` (true: the
// player hull is inside solid there), and the figures its collision tests reported.
CandidateRecord candidate(std::vector<bool> in_solid, const std::string& name = "", int occupied_max = 0,
                          double min_near_ratio = 0) {
  CandidateRecord c;
  c.verdict.candidate = name;
  c.verdict.occupied_max = occupied_max;
  c.verdict.min_near_ratio = min_near_ratio;
  for (bool s : in_solid) c.truth.push_back({Eigen::Isometry3d::Identity(), cv::Mat(), s, 0.0});
  return c;
}

}  // namespace

// Hand-made history: step 1 committed 3 frames, 2 in solid; step 2 stalled (its
// candidates' in-solid frames were never committed); step 3 committed 1 in-solid frame
// of 2; step 4 rewound and committed nothing. 3 in-solid frames were committed.
TEST(EpisodeTruth, CommittedInSolidFramesCountOnlyChosenCandidates) {
  std::vector<StepRecord> history(4);
  history[0].candidates = {candidate({false, false, false}), candidate({false, true, true})};
  history[0].chosen = 1;
  history[1].candidates = {candidate({true, true}), candidate({true})};
  history[2].candidates = {candidate({true, false})};
  history[2].chosen = 0;
  history[3].rewind = true;
  EXPECT_EQ(committedInSolidFrames(history), 3);
  EXPECT_EQ(committedInSolidFrames({}), 0);
}

// The same kind of history: step 2 committed "jw@20" with its 3rd and 4th frames in
// solid, 12 points in its body cylinder and a central depth of 4.6 camera heights;
// step 1 committed a clean "uw"; step 3 stalled with in-solid candidates.
TEST(EpisodeTruth, PenetrationEventsNameTheCommittedStepAndWhatTheTestsSaw) {
  std::vector<StepRecord> history(3);
  history[0].step = 1;
  history[0].candidates = {candidate({false, false}, "uw", 3, 2.0)};
  history[0].chosen = 0;
  history[1].step = 2;
  history[1].candidates = {candidate({true}, "uw", 400, 0.1), candidate({false, false, true, true}, "jw@20", 12, 4.6)};
  history[1].chosen = 1;
  history[2].step = 3;
  history[2].candidates = {candidate({true, true}, "lw", 50, 0.2)};
  const std::vector<PenetrationEvent> events = penetrationEvents(history);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].step, 2);
  EXPECT_EQ(events[0].candidate, "jw@20");
  EXPECT_EQ(events[0].frames, 2);
  EXPECT_EQ(events[0].first_frame, 2);
  EXPECT_EQ(events[0].occupied_max, 12);
  EXPECT_DOUBLE_EQ(events[0].min_near_ratio, 4.6);
  EXPECT_TRUE(penetrationEvents({}).empty());
}
