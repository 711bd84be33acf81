// The engine world model: deterministic rollouts, checkpoints, commits, ground truth,
// degradations, and clear errors for bad maps, archives and spawns.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "openarena_data.h"
#include "valerant/common/error.h"
#include "valerant/world/degradation.h"
#include "valerant/world/quake3/quake3_world.h"

using namespace valerant;
using namespace valerant::quake3;

namespace {

Config smallConfig() {
  Config c;
  c.world.width = 160;
  c.world.height = 120;
  return c;
}

double difference(const cv::Mat& a, const cv::Mat& b) { return cv::norm(a, b, cv::NORM_L1); }

}  // namespace

TEST(Quake3World, RolloutsAreDeterministicAndLeaveTheStateAlone) {
  VALERANT_REQUIRE_OPENARENA();
  const Config config = smallConfig();
  auto map = loadQuake3Map("oa_dm1", config.world.patch_level);
  Quake3World world(map, config);
  const CameraState start = world.camera();
  Quake3World other(map, config);  // one world would reuse its frames
  const Rollout a = world.rollout(makeActionSequence("uw", config));
  const Rollout b = other.rollout(makeActionSequence("uw", config));
  ASSERT_EQ(a.frames.size(), 57u);
  ASSERT_EQ(a.truth.size(), 57u);
  EXPECT_EQ(difference(a.frames.back(), b.frames.back()), 0.0);
  EXPECT_EQ(world.camera().xy, start.xy);  // imagining does not move the world
  // Ground truth: the eye moved 256 units, and depth is finite metres somewhere.
  const Eigen::Vector3d moved =
      a.truth.back().camera_to_world.translation() - world.kinematics().cameraToWorld(start).translation();
  EXPECT_NEAR(moved.head<2>().norm(), 256.0, 1e-6);
  double min_depth = 1e9;
  cv::minMaxLoc(a.truth[0].depth_m, &min_depth, nullptr, nullptr, nullptr, a.truth[0].depth_m == a.truth[0].depth_m);
  EXPECT_GT(min_depth, 0.05);
}

TEST(Quake3World, CommitCheckpointAndRestore) {
  VALERANT_REQUIRE_OPENARENA();
  const Config config = smallConfig();
  auto map = loadQuake3Map("oa_dm1", config.world.patch_level);
  Quake3World world(map, config);
  const CheckpointId start = world.checkpoint();
  ASSERT_EQ(world.context().frames.size(), 1u);  // the single starting screenshot
  const Rollout uw = world.rollout(makeActionSequence("uw", config));
  const Rollout jq = world.rollout(makeActionSequence("jq", config));
  world.commit(jq);
  EXPECT_NEAR(world.camera().yaw_deg - map->bsp.spawnPoints()[0].yaw_deg, 90.0, 1e-9);
  EXPECT_EQ(world.context().frames.size(), 16u);  // K = 16 frames of context
  EXPECT_EQ(difference(world.context().frames.back(), jq.frames.back()), 0.0);
  // uw was made before the commit: it no longer starts from the committed state.
  EXPECT_THROW(world.commit(uw), InputError);
  world.restore(start);
  EXPECT_EQ(world.context().frames.size(), 1u);
  const Rollout again = world.rollout(makeActionSequence("uw", config));
  EXPECT_EQ(difference(again.frames.back(), uw.frames.back()), 0.0);  // same next frames
  world.dropCheckpoint(start);
  EXPECT_THROW(world.restore(start), InputError);
}

// A rollout that begins with another's actions reuses its frames and renders the rest:
// the same frames, truth and end state as a world that renders them all.
TEST(Quake3World, RolloutsBeginningAlikeReuseFrames) {
  VALERANT_REQUIRE_OPENARENA();
  Config config = smallConfig();
  config.world.degradation.noise_sigma = 6;  // keyed by the frame's index: reuse must keep it
  auto map = loadQuake3Map("oa_dm1", config.world.patch_level);
  Quake3World reusing(map, config), rendering(map, config);
  const Rollout uw = reusing.rollout(makeActionSequence("uw", config));
  const Rollout jq = reusing.rollout(makeActionSequence("jq", config));
  const Rollout shorter = reusing.rollout(makeActionSequence("uw@32", config));
  const Rollout longer = reusing.rollout(makeActionSequence("jq:80", config));
  EXPECT_EQ(shorter.frames[31].data, uw.frames[31].data);  // not rendered again
  EXPECT_EQ(longer.frames[56].data, jq.frames[56].data);
  EXPECT_NE(longer.frames[57].data, nullptr);
  for (const auto& [name, made] : {std::pair{"uw@32", &shorter}, std::pair{"jq:80", &longer}}) {
    Quake3World fresh(map, config);
    const Rollout rendered = fresh.rollout(makeActionSequence(name, config));
    ASSERT_EQ(made->frames.size(), rendered.frames.size()) << name;
    for (size_t i = 0; i < rendered.frames.size(); ++i) {
      EXPECT_EQ(difference(made->frames[i], rendered.frames[i]), 0.0) << name << " frame " << i;
      EXPECT_TRUE(made->truth[i].camera_to_world.isApprox(rendered.truth[i].camera_to_world, 0)) << name << " frame " << i;
      EXPECT_EQ(made->truth[i].in_solid, rendered.truth[i].in_solid);
    }
  }
  // Committing a reused rollout reaches the state rendering it would: the same context
  // and the same next frames.
  reusing.commit(longer);
  rendering.commit(rendering.rollout(makeActionSequence("jq:80", config)));
  EXPECT_EQ(reusing.camera().yaw_deg, rendering.camera().yaw_deg);
  ASSERT_EQ(reusing.context().frames.size(), rendering.context().frames.size());
  EXPECT_EQ(difference(reusing.context().frames.front(), rendering.context().frames.front()), 0.0);
  const Rollout next_a = reusing.rollout(makeActionSequence("uw", config));
  const Rollout next_b = rendering.rollout(makeActionSequence("uw", config));
  EXPECT_EQ(difference(next_a.frames.back(), next_b.frames.back()), 0.0);
}

TEST(Quake3World, DegradationsAreDeterministicPerFrame) {
  VALERANT_REQUIRE_OPENARENA();
  Config config = smallConfig();
  config.world.degradation.noise_sigma = 6;
  config.world.degradation.exposure_flicker = 0.2;
  config.world.degradation.jitter_px = 2;
  config.world.degradation.blur_sigma = 0.8;
  auto map = loadQuake3Map("oa_dm1", config.world.patch_level);
  Quake3World noisy(map, config), noisy_again(map, config);  // one world would reuse its frames
  Quake3World clean(map, smallConfig());
  const Rollout a = noisy.rollout(makeActionSequence("uw", config));
  const Rollout b = noisy_again.rollout(makeActionSequence("uw", config));
  const Rollout c = clean.rollout(makeActionSequence("uw", config));
  EXPECT_EQ(difference(a.frames[10], b.frames[10]), 0.0);
  EXPECT_GT(difference(a.frames[10], c.frames[10]), 0.0);
  EXPECT_GT(difference(a.frames[10], a.frames[11]), 0.0);
  EXPECT_FALSE(degradationEnabled(DegradationConfig{}));
}

TEST(Quake3World, BadInputIsNamed) {
  VALERANT_REQUIRE_OPENARENA();
  auto expectInput = [](const std::function<void()>& f, const std::string& input) {
    try {
      f();
      ADD_FAILURE() << "no error for " << input;
    } catch (const InputError& e) {
      EXPECT_EQ(e.input(), input) << e.what();
    }
  };
  expectInput([] { loadQuake3Map("no_such_map", 8); }, "map 'no_such_map'");
  const std::string corrupt = ::testing::TempDir() + "/broken.pk3";
  std::ofstream(corrupt) << "not a zip";
  expectInput([&] { loadQuake3Map(corrupt + ":oa_dm1", 8); }, corrupt);
  expectInput([] { loadQuake3Map("/nonexistent/x.pk3:oa_dm1", 8); }, "/nonexistent/x.pk3");
  Config config = smallConfig();
  config.world.spawn = 99;
  auto map = loadQuake3Map("oa_dm1", 8);
  expectInput([&] { Quake3World world(map, config); }, "spawn 99");
  expectInput([&] { makeActionSequence("zz", config); }, "action 'zz'");
}

TEST(Quake3World, EveryInstalledMapLoadsAndRenders) {
  VALERANT_REQUIRE_OPENARENA();
  const Config config = smallConfig();
  int rendered = 0;
  for (const std::string& name : installedMapNames()) {
    SCOPED_TRACE(name);
    std::shared_ptr<const Quake3Map> map;
    ASSERT_NO_THROW(map = loadQuake3Map(name, 4));
    if (map->bsp.spawnPoints().empty()) continue;  // e.g. single-player scenery maps
    Quake3World world(map, config);
    const cv::Mat frame = world.context().frames.back();
    cv::Scalar mean, stddev;
    cv::meanStdDev(frame, mean, stddev);
    EXPECT_GT(stddev[0] + stddev[1] + stddev[2], 3.0) << "a flat image: nothing rendered";
    ++rendered;
  }
  EXPECT_GT(rendered, 30);
}
