// The pose_anchor warp (pose_warp.h), worked by hand on the cases of
// learn/smoke_test_world_model.py's PoseAnchorWarpTest (the same arithmetic in torch):
// the engine's turn-then-move, a step towards a wall and a strafe along it, the floor's
// fixed point, a turn alone (the rotation warp), the depth carried to a new anchor; and
// the warp through learn/make_test_world_model.py's world_model_pose.onnx (flow 0, mask
// 1 - strafe, fill = the warped newest frame), whose contract the backend checks.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "valerant/common/error.h"
#include "valerant/world/learned/anchor_warp.h"
#include "valerant/world/learned/pose_warp.h"
#include "valerant/world/learned/world_model_net.h"

using namespace valerant;

namespace {

const std::string kPoseModel = std::string(VALERANT_SOURCE_DIR) + "/test/data/world_model_pose.onnx";
const std::string kAnchorModel = std::string(VALERANT_SOURCE_DIR) + "/test/data/world_model_anchor.onnx";
const std::string kDepthPrior = std::string(VALERANT_SOURCE_DIR) + "/models/depth_prior.onnx";

// 90 deg field of view at 128 x 96: fx = fy = 64, cx = 64, cy = 48 from the corner, so
// pixel index x has the ray (x + 0.5 - 64) / 64 and the optical axis lies at 63.5, 47.5.
const CameraIntrinsics kCamera = CameraIntrinsics::fromHorizontalFov(128, 96, 90);

MotionStep motion(double forward, double strafe = 0, double yaw = 0, double pitch = 0) {
  MotionStep m;
  m.forward_units = forward;
  m.strafe_units = strafe;
  m.yaw_deg = yaw;
  m.pitch_deg = pitch;
  return m;
}

cv::Mat constantDepth(double metres) { return cv::Mat(96, 128, CV_32F, cv::Scalar(metres)); }

cv::Mat identityCoords() {
  cv::Mat coords(96, 128, CV_32FC2);
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 128; ++x) coords.at<cv::Vec2f>(y, x) = cv::Vec2f(x, y);
  return coords;
}

cv::Mat randomFrame(int seed) {
  cv::Mat frame(96, 128, CV_8UC3);
  cv::RNG(seed).fill(frame, cv::RNG::UNIFORM, 0, 256);
  return frame;
}

WarpSampling stepFromStart(const cv::Mat& depth, const MotionStep& m) {
  return poseSampling(depth, CameraPose{}, advancePose(CameraPose{}, m), kCamera);
}

}  // namespace

TEST(AdvancePose, TheEngineTurnsThenMovesAlongTheNewHeading) {
  // 90 deg left, then 32 units (1 m) forward: the heading is +y, so the camera ends at
  // (0, 1); then 32 units of strafe to the right of +y, which is +x: (1, 1).
  const CameraPose turned = advancePose(CameraPose{}, motion(32, 0, 90));
  EXPECT_NEAR(turned.x_m, 0.0, 1e-12);
  EXPECT_NEAR(turned.y_m, 1.0, 1e-12);
  EXPECT_EQ(turned.yaw_deg, 90.0);
  const CameraPose strafed = advancePose(turned, motion(0, 32));
  EXPECT_NEAR(strafed.x_m, 1.0, 1e-12);
  EXPECT_NEAR(strafed.y_m, 1.0, 1e-12);
}

TEST(PoseSampling, AStepTowardsAWall) {
  // A wall 2 m ahead, 16 units (0.5 m) forward: the next camera sees it at 1.5 m, so pixel
  // p samples the newest frame at 63.5 + (p - 63.5) * 1.5 / 2 (rows about 47.5): (127, 95)
  // at (111.125, 83.125), (0, 0) at (15.875, 11.875), every position inside the image.
  const WarpSampling s = stepFromStart(constantDepth(2), motion(16));
  EXPECT_NEAR(s.positions.at<cv::Vec2f>(95, 127)[0], 111.125, 1e-4);
  EXPECT_NEAR(s.positions.at<cv::Vec2f>(95, 127)[1], 83.125, 1e-4);
  EXPECT_NEAR(s.positions.at<cv::Vec2f>(0, 0)[0], 15.875, 1e-4);
  EXPECT_NEAR(s.positions.at<cv::Vec2f>(0, 0)[1], 11.875, 1e-4);
  EXPECT_EQ(cv::countNonZero(s.in_view), 96 * 128);
}

TEST(PoseSampling, AStrafeAlongAWall) {
  // 8 units (0.25 m) to the right, the wall at 2 m: every pixel samples 64 * 0.25 / 2 = 8
  // pixels to its right, and the last 8 columns leave the newest image.
  const WarpSampling s = stepFromStart(constantDepth(2), motion(0, 8));
  EXPECT_NEAR(s.positions.at<cv::Vec2f>(10, 0)[0], 8.0, 1e-4);
  EXPECT_NEAR(s.positions.at<cv::Vec2f>(10, 0)[1], 10.0, 1e-4);
  EXPECT_EQ(s.in_view.at<float>(10, 119), 1.f);
  EXPECT_EQ(s.in_view.at<float>(10, 120), 0.f);
}

TEST(PoseSampling, ATurnThenAStep) {
  // 129 x 97 pixels, the axis at pixel (64, 48). 20 deg left, then 16 units (0.5 m) along
  // the new heading: the camera at (0.5 cos 20, 0.5 sin 20) = (0.46985, 0.17101) m, its
  // axis (cos 20, sin 20) meets the wall x = 2 m after (2 - 0.46985) / cos 20 = 1.62836 m,
  // at y = 0.17101 + 1.62836 sin 20 = 0.72794 m: in the newest camera 0.72794 m to the
  // left at depth 2, so pixel (64, 48) samples u = 64 - 64 * 0.72794 / 2 = 40.7059, v = 48.
  CameraIntrinsics camera = kCamera;
  camera.width = 129;
  camera.height = 97;
  camera.cx = 64.5;
  camera.cy = 48.5;
  const cv::Mat wall(97, 129, CV_32F, cv::Scalar(2));
  const WarpSampling s = poseSampling(wall, CameraPose{}, advancePose(CameraPose{}, motion(16, 0, 20)), camera);
  EXPECT_NEAR(s.positions.at<cv::Vec2f>(48, 64)[0], 40.7059, 1e-4);
  EXPECT_NEAR(s.positions.at<cv::Vec2f>(48, 64)[1], 48.0, 1e-5);
  EXPECT_EQ(s.in_view.at<float>(48, 64), 1.f);
}

TEST(PoseSampling, TheFloorConvergesInThreeIterations) {
  // The floor 1.5625 m below a level camera: row v has depth h fy / (v + 0.5 - 48).
  // 4.5 units (0.140625 m) forward, the next frame's bottom row (a = 95 + 0.5 - 48 = 47.5)
  // sees the floor point whose row u (from the axis) solves u = a (1 - f u / (h fy)):
  // u = 47.5 / 1.066796875 = 44.5258, index 92.0258. From the rotation's guess (index 95)
  // the error shrinks by a f / (h fy) = 0.0668 an iteration: 0.0009 px after three.
  cv::Mat floor(96, 128, CV_32F);
  for (int y = 0; y < 96; ++y) floor.row(y).setTo(y > 47 ? 1.5625 * 64 / (y + 0.5 - 48) : 80.0);
  const WarpSampling s = stepFromStart(floor, motion(4.5));
  EXPECT_NEAR(s.positions.at<cv::Vec2f>(95, 64)[1], 47.5 + 47.5 / 1.066796875, 0.0015);
}

TEST(PoseSampling, ATurnAloneIsTheRotationWarp) {
  cv::Mat depth(96, 128, CV_32F);
  cv::RNG(3).fill(depth, cv::RNG::UNIFORM, 1.0, 6.0);
  const MotionStep turn = motion(0, 0, 7, -3);
  const WarpSampling pose = stepFromStart(depth, turn), rotation = rotationSampling(turn, kCamera);
  EXPECT_LE(cv::norm(pose.positions, rotation.positions, cv::NORM_INF), 1e-4);
  EXPECT_EQ(cv::norm(pose.in_view, rotation.in_view, cv::NORM_INF), 0.0);
}

TEST(DepthInCamera, AStepAheadAndAQuarterTurn) {
  // Anchor pixel (64, 48) at depth 2 m (ray x' = 0.5 / 64), the camera 0.5 m ahead: depth
  // 1.5 m; a quarter turn left: the point lies 2 m to that camera's right and
  // 0.5 / 64 * 2 = 0.015625 m behind it, its depth clamped to 0.05.
  const cv::Mat coords = identityCoords();
  CameraPose ahead;
  ahead.x_m = 0.5;
  EXPECT_NEAR(depthInCamera(constantDepth(2), coords, CameraPose{}, ahead, kCamera).at<float>(48, 64), 1.5, 1e-6);
  CameraPose left;
  left.yaw_deg = 90;
  EXPECT_NEAR(depthInCamera(constantDepth(2), coords, CameraPose{}, left, kCamera).at<float>(48, 64), 0.05, 1e-7);
}

TEST(PoseGeometry, AMissingDepthIsTheSky) {
  const cv::Mat depth = (cv::Mat_<float>(1, 2) << std::numeric_limits<float>::quiet_NaN(), 0.01f);
  const PoseGeometry g = PoseGeometry::start(depth, kCamera);
  EXPECT_FLOAT_EQ(g.depth.at<float>(0, 0), 80.f);
  EXPECT_FLOAT_EQ(g.depth.at<float>(0, 1), 0.05f);
}

TEST(AnchorStep, AFilledFrameBecomesTheAnchorWithItsDepthCarried) {
  // The wall at 2 m, 16 units forward, everything filled: the new anchor is the fill, its
  // pose (0.5, 0), its depth the wall's from there, 1.5 m.
  const cv::Mat frame = randomFrame(5);
  AnchorState state = AnchorState::start(frame, PoseGeometry::start(constantDepth(2), kCamera));
  const PoseGeometry moved = state.geometry->moved(motion(16));
  const WarpSampling s = poseSampling(state.geometry->depthOf(state.coords), state.geometry->pose, moved.pose, kCamera);
  const cv::Mat zeros(frame.size(), CV_32F, cv::Scalar(0)), grey(frame.size(), CV_32FC3, cv::Scalar::all(0.2));
  anchorStep(state, frame, s.positions, zeros, grey, moved);
  ASSERT_TRUE(state.geometry.has_value());
  EXPECT_NEAR(state.anchor.at<cv::Vec3f>(10, 10)[0], 51 / 255.0, 1e-6);
  EXPECT_NEAR(state.geometry->anchor_pose.x_m, 0.5, 1e-12);
  EXPECT_NEAR(state.geometry->pose.x_m, 0.5, 1e-12);
  double low, high;
  cv::minMaxLoc(state.geometry->depth, &low, &high);
  EXPECT_NEAR(low, 1.5, 1e-5);
  EXPECT_NEAR(high, 1.5, 1e-5);
}

TEST(WorldModelNetPose, AStepForwardIsThePoseWarp) {
  auto prior = std::make_shared<const DepthPrior>(kDepthPrior, cv::Size(128, 96));
  WorldModelNet net(kPoseModel, 128, 96, 4, WorldWarp::kPoseAnchor, 90, prior);
  const cv::Mat newest = randomFrame(7);
  const std::vector<cv::Mat> context = {randomFrame(1), randomFrame(2), randomFrame(3), newest};
  // The prior's depth of the first anchor: startAnchor runs it on the frame.
  const AnchorState started = net.startAnchor(newest);
  ASSERT_TRUE(started.geometry.has_value());
  EXPECT_LE(cv::norm(started.geometry->depth, prior->predict(newest).depth_m, cv::NORM_INF), 1e-6);
  // With the wall at 2 m: mask 1, flow 0, so pixel (127, 95) is the newest frame at
  // (111.125, 83.125): weights 0.875 * 0.875, 0.125 * 0.875, 0.875 * 0.125, 0.125 * 0.125
  // on pixels (111, 83), (112, 83), (111, 84), (112, 84).
  AnchorState state = AnchorState::start(newest, PoseGeometry::start(constantDepth(2), kCamera));
  const cv::Mat next = net.next(context, motion(16), state);
  const auto red = [&](int y, int x) { return static_cast<double>(newest.at<cv::Vec3b>(y, x)[0]); };
  const double expected = 0.765625 * red(83, 111) + 0.109375 * red(83, 112) + 0.109375 * red(84, 111) +
                          0.015625 * red(84, 112);
  EXPECT_NEAR(next.at<cv::Vec3b>(95, 127)[0], expected, 0.5 + 1e-3);
  EXPECT_NEAR(state.geometry->pose.x_m, 0.5, 1e-12);
}

TEST(WorldModelNetPose, AModelOfAnotherWarpIsAnErrorNamingTheFile) {
  auto prior = std::make_shared<const DepthPrior>(kDepthPrior, cv::Size(128, 96));
  const auto message = [&](const std::string& model, WorldWarp warp, std::shared_ptr<const DepthPrior> p) {
    try {
      WorldModelNet net(model, 128, 96, 4, warp, 90, std::move(p));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // v3's contract (rotation_anchor) configured as pose_anchor, and the reverse.
  const std::string v3_as_pose = message(kAnchorModel, WorldWarp::kPoseAnchor, prior);
  EXPECT_NE(v3_as_pose.find(kAnchorModel), std::string::npos) << v3_as_pose;
  EXPECT_NE(v3_as_pose.find("has no input 'frames_motion_and_pose_warp', which a model of the pose_anchor warp reads"),
            std::string::npos)
      << v3_as_pose;
  const std::string pose_as_v3 = message(kPoseModel, WorldWarp::kRotationAnchor, nullptr);
  EXPECT_NE(pose_as_v3.find(kPoseModel + ": has no input 'frames_and_motion'"), std::string::npos) << pose_as_v3;
  const std::string no_prior = message(kPoseModel, WorldWarp::kPoseAnchor, nullptr);
  EXPECT_NE(no_prior.find("needs the depth prior"), std::string::npos) << no_prior;
  EXPECT_EQ(parseWorldWarp("pose_anchor"), WorldWarp::kPoseAnchor);
  EXPECT_STREQ(worldWarpName(WorldWarp::kPoseAnchor), "pose_anchor");
}
