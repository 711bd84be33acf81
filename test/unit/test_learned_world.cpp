// The learned world backend on the hand-made shift model (learn/make_test_world_model.py:
// dx = -yaw_deg, dy = pitch_deg, mask = 1 - strafe_units): the screenshot and engine
// starts, frames worked out by hand, checkpoints, commits, the engine shadow's truth,
// and clear errors for bad images and models.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <unistd.h>

#include "openarena_data.h"
#include "valerant/common/error.h"
#include "valerant/world/learned/learned_world.h"

using namespace valerant;

namespace {

const std::string kShiftModel = std::string(VALERANT_SOURCE_DIR) + "/test/data/world_model_shift.onnx";
const std::string kAnchorModel = std::string(VALERANT_SOURCE_DIR) + "/test/data/world_model_anchor.onnx";
const std::string kPoseModel = std::string(VALERANT_SOURCE_DIR) + "/test/data/world_model_pose.onnx";

// The shift model's frames are worked out by hand with the last_frame warp; the anchor
// model (flow 0, mask 1: the rotation warp alone) exercises rotation_anchor's state.
Config smallConfig(const std::string& model = kShiftModel, const std::string& warp = "last_frame") {
  Config c;
  c.world.backend = "learned";
  c.world.width = 160;
  c.world.height = 120;
  c.world.learned.model = model;
  c.world.learned.warp = warp;
  return c;
}

// A smooth 640 x 480 picture with texture in both directions.
cv::Mat screenshot() {
  cv::Mat rgb(480, 640, CV_8UC3);
  for (int y = 0; y < rgb.rows; ++y)
    for (int x = 0; x < rgb.cols; ++x)
      rgb.at<cv::Vec3b>(y, x) = cv::Vec3b(x * 255 / 639, y * 255 / 479, (x * y / 37) % 256);
  return rgb;
}

// `frame` moved by whole pixels: result(x, y) = frame(x + dx, y + dy), edges replicated.
cv::Mat shiftedByHand(const cv::Mat& frame, int dx, int dy) {
  cv::Mat out(frame.size(), frame.type());
  for (int y = 0; y < frame.rows; ++y)
    for (int x = 0; x < frame.cols; ++x)
      out.at<cv::Vec3b>(y, x) =
          frame.at<cv::Vec3b>(std::clamp(y + dy, 0, frame.rows - 1), std::clamp(x + dx, 0, frame.cols - 1));
  return out;
}

cv::Mat resized(const cv::Mat& rgb, cv::Size size, int interpolation) {
  cv::Mat out;
  cv::resize(rgb, out, size, 0, 0, interpolation);
  return out;
}

// `frames` steps turning right by 1 degree each: the shift model moves the picture one
// pixel left per frame.
ActionSequence turnRight(int frames) {
  ActionSequence a;
  a.name = "right" + std::to_string(frames);
  MotionStep step;
  step.yaw_deg = -1;
  a.steps.assign(frames, step);
  return a;
}

double differences(const cv::Mat& a, const cv::Mat& b) { return cv::norm(a, b, cv::NORM_INF); }

void expectSameFrames(const Rollout& a, const Rollout& b) {
  ASSERT_EQ(a.frames.size(), b.frames.size());
  for (size_t i = 0; i < a.frames.size(); ++i) EXPECT_EQ(differences(a.frames[i], b.frames[i]), 0.0) << "frame " << i;
}

std::unique_ptr<LearnedWorld> screenshotWorld(const Config& config) {
  return LearnedWorld::fromScreenshot(loadWorldModelNet(config), screenshot(), config);
}

std::string scratchFile(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("valerant_learned_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

template <typename F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(LearnedWorld, ScreenshotStartShowsTheImageAtTheWorldCameraWithoutTruth) {
  const Config config = smallConfig();
  auto world = screenshotWorld(config);
  EXPECT_EQ(world->shadow(), nullptr);
  const CameraIntrinsics expected = CameraIntrinsics::fromHorizontalFov(160, 120, 90);
  EXPECT_EQ(world->intrinsics().width, 160);
  EXPECT_EQ(world->intrinsics().height, 120);
  EXPECT_DOUBLE_EQ(world->intrinsics().fx, expected.fx);
  EXPECT_DOUBLE_EQ(world->intrinsics().cx, expected.cx);

  // The screenshot at the net's size (INTER_AREA), shown at the camera's (INTER_LINEAR).
  const cv::Mat start = resized(screenshot(), cv::Size(128, 96), cv::INTER_AREA);
  const Rollout context = world->context();
  ASSERT_EQ(context.frames.size(), 1u);  // one frame, though the net sees it K times
  EXPECT_TRUE(context.truth.empty());
  EXPECT_EQ(differences(context.frames[0], resized(start, cv::Size(160, 120), cv::INTER_LINEAR)), 0.0);

  // Three steps right: the start moved 1, 2, 3 pixels left at the net's size.
  const Rollout r = world->rollout(turnRight(3));
  EXPECT_EQ(r.candidate, "right3");
  ASSERT_EQ(r.frames.size(), 3u);
  EXPECT_TRUE(r.truth.empty());
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(r.frames[i].type(), CV_8UC3);
    EXPECT_EQ(differences(r.frames[i], resized(shiftedByHand(start, i + 1, 0), cv::Size(160, 120), cv::INTER_LINEAR)),
              0.0)
        << "frame " << i;
  }
}

TEST(LearnedWorld, RolloutsLeaveTheStateAloneCommitsSlideTheContextRestoresRepeat) {
  const Config config = smallConfig();
  auto world = screenshotWorld(config);
  const CheckpointId start = world->checkpoint();
  const Rollout context = world->context();
  const Rollout jq = world->rollout(makeActionSequence("jq", config));
  const Rollout uw = world->rollout(makeActionSequence("uw", config));
  ASSERT_EQ(jq.frames.size(), 57u);
  // Imagining changes nothing: the same keys give the same bytes, the context is as it was.
  expectSameFrames(world->rollout(makeActionSequence("jq", config)), jq);
  ASSERT_EQ(world->context().frames.size(), 1u);
  EXPECT_EQ(differences(world->context().frames[0], context.frames[0]), 0.0);

  world->commit(jq);
  const Rollout after = world->context();
  ASSERT_EQ(after.frames.size(), 4u);  // the last K = 4 committed frames
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(differences(after.frames[i], jq.frames[53 + i]), 0.0);
  // uw was made before the commit: it no longer starts from the committed state.
  EXPECT_NE(errorOf([&] { world->commit(uw); }).find("rollout " + std::to_string(uw.id)), std::string::npos);
  const Rollout lq = world->rollout(makeActionSequence("lq", config));
  const CheckpointId turned = world->checkpoint();
  world->commit(lq);

  world->restore(start);
  EXPECT_EQ(world->context().frames.size(), 1u);
  expectSameFrames(world->rollout(makeActionSequence("jq", config)), jq);
  expectSameFrames(world->rollout(makeActionSequence("uw", config)), uw);
  world->restore(turned);
  expectSameFrames(world->rollout(makeActionSequence("lq", config)), lq);
  // Stale after a restore, and a rollout this world never made.
  EXPECT_THROW(world->commit(lq), InputError);
  Rollout foreign;
  foreign.id = 999;
  EXPECT_THROW(world->commit(foreign), InputError);
  world->dropCheckpoint(start);
  EXPECT_THROW(world->restore(start), InputError);
}

TEST(LearnedWorld, AnchorWarpStateIsCommittedCheckpointedAndRestored) {
  const Config config = smallConfig(kAnchorModel, "rotation_anchor");
  auto world = screenshotWorld(config);
  const CheckpointId start = world->checkpoint();
  // Committing a turn and turning on continues the same anchor: the frames are those of
  // one rollout of both turns' keys (j at jq's rate, then l at lq's).
  const Rollout both = world->rollout(makeActionSequence("j:57,l:20", config));
  const Rollout jq = world->rollout(makeActionSequence("jq", config));
  for (size_t i = 0; i < jq.frames.size(); ++i)
    EXPECT_EQ(differences(jq.frames[i], both.frames[i]), 0.0) << "frame " << i;
  world->commit(jq);
  const CheckpointId turned = world->checkpoint();
  const Rollout left = world->rollout(makeActionSequence("l:20", config));
  ASSERT_EQ(left.frames.size(), 20u);
  for (size_t i = 0; i < 20; ++i) EXPECT_EQ(differences(left.frames[i], both.frames[57 + i]), 0.0) << "frame " << i;
  // A later commit leaves the checkpoints' anchors as they were.
  world->commit(world->rollout(makeActionSequence("uw", config)));
  world->restore(turned);
  expectSameFrames(world->rollout(makeActionSequence("l:20", config)), left);
  world->restore(start);
  expectSameFrames(world->rollout(makeActionSequence("j:57,l:20", config)), both);
}

TEST(LearnedWorld, PoseAnchorWarpStateIsCommittedCheckpointedAndRestored) {
  // The pose model (flow 0, mask 1: the pose warp alone) from a screenshot, its first
  // anchor's depth the shipped depth prior's: committing a walk and walking on continues
  // the same anchor, depth and poses, as one rollout of both keys does.
  const Config config = smallConfig(kPoseModel, "pose_anchor");
  auto world = screenshotWorld(config);
  const CheckpointId start = world->checkpoint();
  const Rollout both = world->rollout(makeActionSequence("jw:30,w:20", config));
  const Rollout first = world->rollout(makeActionSequence("jw:30", config));
  world->commit(first);
  const Rollout then = world->rollout(makeActionSequence("w:20", config));
  ASSERT_EQ(then.frames.size(), 20u);
  for (size_t i = 0; i < 20; ++i) EXPECT_EQ(differences(then.frames[i], both.frames[30 + i]), 0.0) << "frame " << i;
  // Walking forward changes the picture (the parallax is geometry, not a repeat).
  EXPECT_GT(differences(then.frames.back(), first.frames.back()), 0.0);
  world->restore(start);
  expectSameFrames(world->rollout(makeActionSequence("jw:30,w:20", config)), both);
}

TEST(LearnedWorld, SameContextAndKeysGiveTheSameBytesInAnotherInstance) {
  const Config config = smallConfig();
  auto a = screenshotWorld(config);
  auto b = screenshotWorld(config);
  a->commit(a->rollout(makeActionSequence("jw", config)));
  b->commit(b->rollout(makeActionSequence("jw", config)));
  expectSameFrames(a->rollout(makeActionSequence("lw", config)), b->rollout(makeActionSequence("lw", config)));
}

TEST(LearnedWorld, BadScreenshotIsAnErrorNamingTheFile) {
  EXPECT_EQ(errorOf([] { readScreenshot("/nonexistent/shot.png"); }),
            "/nonexistent/shot.png: screenshot file does not exist");
  const std::string text = scratchFile("text.png");
  std::ofstream(text) << "not an image";
  const std::string empty = scratchFile("empty.png");
  std::ofstream{empty};
  const std::string text_error = errorOf([&] { readScreenshot(text); });
  const std::string empty_error = errorOf([&] { readScreenshot(empty); });
  std::filesystem::remove(text);
  std::filesystem::remove(empty);
  EXPECT_NE(text_error.find(text + ": not an image"), std::string::npos) << text_error;
  EXPECT_NE(empty_error.find(empty + ": not an image"), std::string::npos) << empty_error;
  EXPECT_NE(errorOf([] { readScreenshot("/tmp"); }).find("/tmp: screenshot is not a file"), std::string::npos);
  const Config config = smallConfig();
  EXPECT_NE(errorOf([&] { LearnedWorld::fromScreenshot(loadWorldModelNet(config), cv::Mat(), config); })
                .find("screenshot: must be a non-empty CV_8UC3 RGB image"),
            std::string::npos);
}

TEST(LearnedWorld, ScreenshotFileReadsAsRgb) {
  const std::string path = scratchFile("shot.png");
  cv::Mat bgr;
  cv::cvtColor(screenshot(), bgr, cv::COLOR_RGB2BGR);
  cv::imwrite(path, bgr);
  const cv::Mat rgb = readScreenshot(path);
  std::filesystem::remove(path);
  EXPECT_EQ(differences(rgb, screenshot()), 0.0);
}

TEST(LearnedWorld, MissingModelIsAnErrorNamingIt) {
  Config config = smallConfig();
  config.world.learned.model = "/nonexistent/world_model.onnx";
  EXPECT_EQ(errorOf([&] { loadWorldModelNet(config); }),
            "/nonexistent/world_model.onnx: world model file does not exist");
}

TEST(LearnedWorld, EngineStartGivesTheShadowsTruthWithTheNetsFrames) {
  VALERANT_REQUIRE_OPENARENA();
  const Config config = smallConfig();
  auto map = quake3::loadQuake3Map("oa_dm1", config.world.patch_level);
  auto world = LearnedWorld::fromSpawn(loadWorldModelNet(config), map, config);
  quake3::Quake3World engine(map, config);  // the same moves on the engine alone
  ASSERT_NE(world->shadow(), nullptr);

  const Rollout context = world->context();
  ASSERT_EQ(context.frames.size(), 1u);
  ASSERT_EQ(context.truth.size(), 1u);
  EXPECT_TRUE(context.truth[0].camera_to_world.isApprox(engine.context().truth[0].camera_to_world));
  // The start is the engine's spawn view at the net's size; the frames are the net's.
  const cv::Mat start = resized(engine.context().frames[0], cv::Size(128, 96), cv::INTER_AREA);
  const Rollout right = world->rollout(turnRight(3));
  ASSERT_EQ(right.truth.size(), right.frames.size());
  EXPECT_EQ(differences(right.frames[2], resized(shiftedByHand(start, 3, 0), cv::Size(160, 120), cv::INTER_LINEAR)),
            0.0);
  const Rollout engine_right = engine.rollout(turnRight(3));
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_TRUE(right.truth[i].camera_to_world.isApprox(engine_right.truth[i].camera_to_world)) << i;
    EXPECT_EQ(right.truth[i].in_solid, engine_right.truth[i].in_solid);
    EXPECT_EQ(right.truth[i].depth_m.size(), cv::Size(160, 120));
  }

  // Commit, checkpoint and restore move the shadow along: its truth follows the engine's.
  const CheckpointId before = world->checkpoint();
  const Rollout uw = world->rollout(makeActionSequence("uw", config));
  ASSERT_EQ(uw.truth.size(), uw.frames.size());
  world->commit(uw);
  engine.commit(engine.rollout(makeActionSequence("uw", config)));
  const Rollout next = world->rollout(makeActionSequence("jq", config));
  const Rollout engine_next = engine.rollout(makeActionSequence("jq", config));
  ASSERT_EQ(next.truth.size(), 57u);
  EXPECT_TRUE(next.truth.back().camera_to_world.isApprox(engine_next.truth.back().camera_to_world));
  EXPECT_EQ(world->context().truth.size(), world->context().frames.size());
  world->restore(before);
  const Rollout again = world->rollout(makeActionSequence("uw", config));
  expectSameFrames(again, uw);
  EXPECT_TRUE(again.truth.back().camera_to_world.isApprox(uw.truth.back().camera_to_world));
}
