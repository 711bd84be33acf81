// The rotation_anchor warp (anchor_warp.h), worked by hand: the rotation's sampling
// positions for a 45 degree turn and a one-pixel pitch, bilinear sampling with both
// paddings, the anchor sampled once over two half-pixel steps, re-anchoring; and the
// warp through an ONNX model (learn/make_test_world_model.py's world_model_anchor.onnx:
// flow 0, mask 1 - strafe, fill = the turned newest frame), whose errors name the model.
#include <gtest/gtest.h>

#include <cmath>

#include "valerant/common/error.h"
#include "valerant/world/learned/anchor_warp.h"
#include "valerant/world/learned/world_model_net.h"

using namespace valerant;

namespace {

const std::string kAnchorModel = std::string(VALERANT_SOURCE_DIR) + "/test/data/world_model_anchor.onnx";

CameraIntrinsics camera(int width, int height, double cx, double cy) {
  CameraIntrinsics k;
  k.width = width;
  k.height = height;
  k.fx = k.fy = 64;
  k.cx = cx;
  k.cy = cy;
  return k;
}

cv::Mat randomFrame(int seed) {
  cv::Mat frame(96, 128, CV_8UC3);
  cv::RNG(seed).fill(frame, cv::RNG::UNIFORM, 0, 256);
  return frame;
}

// The row 0 1 0 1 0 1 (two rows, so that a row coordinate exists), as 8-bit RGB.
cv::Mat alternatingRows() {
  cv::Mat frame(2, 6, CV_8UC3);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 6; ++x) frame.at<cv::Vec3b>(y, x) = cv::Vec3b::all(x % 2 ? 255 : 0);
  return frame;
}

cv::Mat shiftedGrid(cv::Size size, float dx) {
  cv::Mat positions(size, CV_32FC2);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) positions.at<cv::Vec2f>(y, x) = cv::Vec2f(x + dx, y);
  return positions;
}

std::vector<int> redRow(const cv::Mat& frame) {
  std::vector<int> row;
  for (int x = 0; x < frame.cols; ++x) row.push_back(frame.at<cv::Vec3b>(0, x)[0]);
  return row;
}

}  // namespace

TEST(RotationSampling, NoRotationSamplesEveryPixelInPlace) {
  const WarpSampling r = rotationSampling(MotionStep{}, camera(128, 96, 64, 48));
  for (int y : {0, 47, 95})
    for (int x : {0, 63, 127}) {
      EXPECT_NEAR(r.positions.at<cv::Vec2f>(y, x)[0], x, 1e-4);
      EXPECT_NEAR(r.positions.at<cv::Vec2f>(y, x)[1], y, 1e-4);
      EXPECT_EQ(r.in_view.at<float>(y, x), 1.f);
    }
}

TEST(RotationSampling, FortyFiveDegreesLeft) {
  // 129 x 97 pixels, principal point at corner coordinate (64.5, 48.5): pixel (64, 48) is
  // the optical axis and pixel 128's ray has x = (128.5 - 64.5) / 64 = 1. Turning 45 deg
  // left, the new axis is the old ray x = -1: corner 0.5, pixel index 0. The new ray x = 1
  // is the old axis (x2 = cos 45 - sin 45 = 0, z2 = sqrt 2): index 64. Row 0 (y = -0.75)
  // at column 128 lands at v = 64 (-0.75) / sqrt 2 + 48 = 14.059.
  MotionStep left;
  left.yaw_deg = 45;
  const WarpSampling r = rotationSampling(left, camera(129, 97, 64.5, 48.5));
  EXPECT_NEAR(r.positions.at<cv::Vec2f>(48, 64)[0], 0.0, 1e-4);
  EXPECT_NEAR(r.positions.at<cv::Vec2f>(48, 64)[1], 48.0, 1e-4);
  EXPECT_NEAR(r.positions.at<cv::Vec2f>(48, 128)[0], 64.0, 1e-4);
  EXPECT_NEAR(r.positions.at<cv::Vec2f>(0, 128)[1], 48 - 48 / std::sqrt(2.0), 1e-4);
  EXPECT_EQ(r.in_view.at<float>(48, 63), 0.f);  // left of the new axis: outside the old image
  EXPECT_EQ(r.in_view.at<float>(48, 64), 1.f);
}

TEST(RotationSampling, LookingDownMovesThePictureUp) {
  // Pitch down by atan(1/64): the centre ray samples one row lower.
  MotionStep down;
  down.pitch_deg = std::atan(1.0 / 64) * 180 / M_PI;
  const WarpSampling r = rotationSampling(down, camera(128, 97, 64, 48.5));
  EXPECT_NEAR(r.positions.at<cv::Vec2f>(48, 64)[1], 49.0, 1e-4);
}

TEST(RotationSampling, RaysBehindTheCameraAreOutOfView) {
  MotionStep about;
  about.yaw_deg = 180;
  const WarpSampling r = rotationSampling(about, camera(128, 96, 64, 48));
  EXPECT_EQ(cv::countNonZero(r.in_view), 0);
}

TEST(SampleBilinear, BorderAndZeroPadding) {
  // 0 10 20 at x = 2.5: border padding clamps to 2 -> 20; zeros padding weighs
  // 20 * 0.5 + 0 * 0.5 = 10. At x = 0.25: 0.75 * 0 + 0.25 * 10 = 2.5 either way.
  const cv::Mat row = (cv::Mat_<float>(2, 3) << 0, 10, 20, 0, 10, 20);
  cv::Mat positions(1, 2, CV_32FC2);
  positions.at<cv::Vec2f>(0, 0) = cv::Vec2f(2.5f, 0);
  positions.at<cv::Vec2f>(0, 1) = cv::Vec2f(0.25f, 1);
  const cv::Mat border = sampleBilinear(row, positions, false), zeros = sampleBilinear(row, positions, true);
  EXPECT_FLOAT_EQ(border.at<float>(0, 0), 20.f);
  EXPECT_FLOAT_EQ(zeros.at<float>(0, 0), 10.f);
  EXPECT_FLOAT_EQ(border.at<float>(0, 1), 2.5f);
  EXPECT_FLOAT_EQ(zeros.at<float>(0, 1), 2.5f);
}

TEST(AnchorStep, TheAnchorIsSampledOnce) {
  // 0 1 0 1 0 1 moved half a pixel twice. Resampling the last frame gives 0.5, then 0.5;
  // through the coordinates the second frame is the anchor moved one whole pixel,
  // 1 0 1 0, on columns 0-3. Column 4 samples validity 0.5 (between a valid column and
  // column 5, invalid after the first step: its 5.5 fell outside), column 5 lies
  // outside: both come from the newest frame at 4.5 (0.5 and 1 -> 0.75) and at 5.5
  // (clamped: 1). 4 of 6 pixels stay valid, at least 0.6: no re-anchoring.
  const cv::Mat anchor = alternatingRows();
  AnchorState state = AnchorState::start(anchor);
  const cv::Mat shift = shiftedGrid(anchor.size(), 0.5f);
  const cv::Mat ones(anchor.size(), CV_32F, cv::Scalar(1)), black(anchor.size(), CV_32FC3, cv::Scalar::all(0));
  const cv::Mat first = anchorStep(state, anchor, shift, ones, black);
  EXPECT_EQ(redRow(first), (std::vector<int>{128, 128, 128, 128, 128, 255}));  // 127.5 rounds to 128
  EXPECT_EQ(cv::countNonZero(state.valid.row(0)), 5);
  const cv::Mat anchor_before = state.anchor;
  const cv::Mat second = anchorStep(state, first, shift, ones, black);
  // Column 4: the mean of 128/255 and 1 is 191.5/255, rounded either way in float.
  const std::vector<int> row = redRow(second);
  EXPECT_EQ(std::vector<int>(row.begin(), row.begin() + 4), (std::vector<int>{255, 0, 255, 0}));
  EXPECT_NEAR(row[4], 191.5, 0.5);
  EXPECT_EQ(row[5], 255);
  EXPECT_EQ(cv::countNonZero(state.valid.row(0)), 4);
  EXPECT_EQ(state.anchor.data, anchor_before.data);  // not re-anchored
}

TEST(AnchorStep, AFilledFrameBecomesTheAnchor) {
  const cv::Mat anchor = alternatingRows();
  AnchorState state = AnchorState::start(anchor);
  const cv::Mat before_coords = state.coords;
  const cv::Mat zeros(anchor.size(), CV_32F, cv::Scalar(0)), grey(anchor.size(), CV_32FC3, cv::Scalar::all(0.2));
  const cv::Mat next = anchorStep(state, anchor, shiftedGrid(anchor.size(), 0.f), zeros, grey);
  EXPECT_EQ(redRow(next), std::vector<int>(6, 51));
  EXPECT_EQ(cv::countNonZero(state.valid), 12);  // a fresh anchor: all valid
  EXPECT_NEAR(state.anchor.at<cv::Vec3f>(1, 3)[0], 51 / 255.0, 1e-6);
  EXPECT_EQ(state.coords.at<cv::Vec2f>(1, 3), cv::Vec2f(3, 1));
  EXPECT_NE(state.coords.data, before_coords.data);  // replaced, not written: checkpoints share them
}

TEST(WorldModelNetAnchor, ATurnIsTheRotationWarp) {
  WorldModelNet net(kAnchorModel, 128, 96, 4, WorldWarp::kRotationAnchor, 90);
  const cv::Mat newest = randomFrame(7);
  const std::vector<cv::Mat> context = {randomFrame(1), randomFrame(2), randomFrame(3), newest};
  AnchorState state = AnchorState::start(newest);
  MotionStep turn;
  turn.yaw_deg = 1.6;
  const cv::Mat next = net.next(context, turn, state);
  // Mask 1, flow 0: every pixel is the newest frame at the rotation's position (from the
  // anchor, which is the newest frame, or from the newest frame itself: the same value).
  cv::Mat newest_unit, expected_unit, expected;
  newest.convertTo(newest_unit, CV_32FC3, 1.0 / 255);
  expected_unit = sampleBilinear(newest_unit, rotationSampling(turn, CameraIntrinsics::fromHorizontalFov(128, 96, 90)).positions, false);
  expected_unit.convertTo(expected, CV_8UC3, 255);
  EXPECT_LE(cv::norm(next, expected, cv::NORM_INF), 1.0);
  // A strafe of 1: mask 0, the fill, i.e. the turned frame the net read from its input.
  MotionStep strafe = turn;
  strafe.strafe_units = 1;
  AnchorState fresh = AnchorState::start(newest);
  EXPECT_LE(cv::norm(net.next(context, strafe, fresh), expected, cv::NORM_INF), 1.0);
}

TEST(WorldModelNetAnchor, WrongWarpOrStateIsAnErrorNamingTheModel) {
  // The anchor model read as a last_frame model gets 16 planes for its 20 input channels.
  try {
    WorldModelNet net(kAnchorModel, 128, 96, 4, WorldWarp::kLastFrame, 90);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(kAnchorModel), std::string::npos) << what;
    EXPECT_NE(what.find("last_frame warp"), std::string::npos) << what;
  }
  WorldModelNet net(kAnchorModel, 128, 96, 4, WorldWarp::kRotationAnchor, 90);
  AnchorState not_started;
  try {
    net.next({randomFrame(1), randomFrame(2), randomFrame(3), randomFrame(4)}, MotionStep{}, not_started);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not started"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parseWorldWarp("anchor"), InputError);
  EXPECT_EQ(parseWorldWarp("rotation_anchor"), WorldWarp::kRotationAnchor);
}
