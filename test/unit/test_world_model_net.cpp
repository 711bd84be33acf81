// One step of the learned world model: the warp-and-blend worked by hand, an ONNX round
// trip through OpenCV DNN on a hand-made model (learn/make_test_world_model.py: dx =
// -yaw_deg, dy = pitch_deg, mask = 1 - strafe_units, fill = the newest frame), and
// errors that name the model file.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "valerant/common/error.h"
#include "valerant/world/learned/world_model_net.h"

using namespace valerant;

namespace {

const std::string kShiftModel = std::string(VALERANT_SOURCE_DIR) + "/test/data/world_model_shift.onnx";
constexpr int kWidth = 128, kHeight = 96, kContext = 4;

std::string loadError(const std::string& path, int context_frames = kContext) {
  try {
    WorldModelNet net(path, kWidth, kHeight, context_frames, WorldWarp::kLastFrame, 90);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A 4 x 1 RGB row with red 0, 40, 80, 120, green 10 more, blue 20 more.
cv::Mat rampRow() {
  cv::Mat row(1, 4, CV_8UC3);
  for (int x = 0; x < 4; ++x) row.at<cv::Vec3b>(0, x) = cv::Vec3b(40 * x, 40 * x + 10, 40 * x + 20);
  return row;
}

cv::Mat randomFrame(int seed) {
  cv::Mat frame(kHeight, kWidth, CV_8UC3);
  cv::RNG(seed).fill(frame, cv::RNG::UNIFORM, 0, 256);
  return frame;
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

double differences(const cv::Mat& a, const cv::Mat& b) { return cv::norm(a, b, cv::NORM_INF); }

}  // namespace

TEST(WarpAndFill, FlowOneRightWithMaskOneShiftsTheImageOnePixelLeft) {
  const cv::Mat last = rampRow();
  const cv::Mat flow(last.size(), CV_32FC2, cv::Scalar(1, 0));
  const cv::Mat mask(last.size(), CV_32F, cv::Scalar(1));
  const cv::Mat fill(last.size(), CV_32FC3, cv::Scalar(0, 0, 0));
  const cv::Mat next = warpAndFill(last, flow, mask, fill);
  ASSERT_EQ(next.type(), CV_8UC3);
  // next(x) = last(x + 1); the last column samples past the edge: replicated.
  EXPECT_EQ(next.at<cv::Vec3b>(0, 0), cv::Vec3b(40, 50, 60));
  EXPECT_EQ(next.at<cv::Vec3b>(0, 1), cv::Vec3b(80, 90, 100));
  EXPECT_EQ(next.at<cv::Vec3b>(0, 2), cv::Vec3b(120, 130, 140));
  EXPECT_EQ(next.at<cv::Vec3b>(0, 3), cv::Vec3b(120, 130, 140));
}

TEST(WarpAndFill, HalfPixelFlowIsBilinear) {
  const cv::Mat last = rampRow();
  const cv::Mat flow(last.size(), CV_32FC2, cv::Scalar(-0.5, 0));
  const cv::Mat next =
      warpAndFill(last, flow, cv::Mat(last.size(), CV_32F, cv::Scalar(1)), cv::Mat(last.size(), CV_32FC3, cv::Scalar(0, 0, 0)));
  // next(x) = (last(x - 1) + last(x)) / 2; x = 0 reads last(-0.5): the edge, replicated.
  EXPECT_EQ(next.at<cv::Vec3b>(0, 0), cv::Vec3b(0, 10, 20));
  EXPECT_EQ(next.at<cv::Vec3b>(0, 1), cv::Vec3b(20, 30, 40));
  EXPECT_EQ(next.at<cv::Vec3b>(0, 3), cv::Vec3b(100, 110, 120));
}

TEST(WarpAndFill, MaskBlendsTheFillAndTheResultIsClampedAndRounded) {
  const cv::Mat last(1, 3, CV_8UC3, cv::Scalar(0, 0, 0));
  const cv::Mat flow(last.size(), CV_32FC2, cv::Scalar(0, 0));
  cv::Mat mask(last.size(), CV_32F);
  mask.at<float>(0, 0) = 0;     // the fill alone
  mask.at<float>(0, 1) = 0.25;  // a quarter black, three quarters fill
  mask.at<float>(0, 2) = 0;
  cv::Mat fill(last.size(), CV_32FC3);
  fill.at<cv::Vec3f>(0, 0) = cv::Vec3f(0.5f, 0.2f, 1.0f);
  fill.at<cv::Vec3f>(0, 1) = cv::Vec3f(1.0f, 0.4f, 0.0f);
  fill.at<cv::Vec3f>(0, 2) = cv::Vec3f(1.5f, -0.2f, 0.999f);  // outside [0,1]: clamped
  const cv::Mat next = warpAndFill(last, flow, mask, fill);
  // 0.5 * 255 = 127.5 -> 128, 0.2 * 255 = 51, 1 -> 255.
  EXPECT_EQ(next.at<cv::Vec3b>(0, 0), cv::Vec3b(128, 51, 255));
  // 0.75 * 255 = 191.25 -> 191, 0.75 * 0.4 * 255 = 76.5 -> 76 or 77 (float), 0.
  const cv::Vec3b blended = next.at<cv::Vec3b>(0, 1);
  EXPECT_EQ(blended[0], 191);
  EXPECT_NEAR(blended[1], 76.5, 0.5);
  EXPECT_EQ(blended[2], 0);
  // 0.999 * 255 = 254.745 -> 255.
  EXPECT_EQ(next.at<cv::Vec3b>(0, 2), cv::Vec3b(255, 0, 255));
}

TEST(WorldModelNet, ShiftModelGivesTheHandWorkedFrame) {
  WorldModelNet net(kShiftModel, kWidth, kHeight, kContext, WorldWarp::kLastFrame, 90);
  EXPECT_EQ(net.width(), kWidth);
  EXPECT_EQ(net.height(), kHeight);
  EXPECT_EQ(net.contextFrames(), kContext);
  EXPECT_EQ(net.path(), kShiftModel);
  const std::vector<cv::Mat> context = {randomFrame(1), randomFrame(2), randomFrame(3), randomFrame(4)};
  const cv::Mat& newest = context.back();

  MotionStep turn_right;  // yaw -2 deg: dx = 2, the picture moves two pixels left
  turn_right.yaw_deg = -2;
  turn_right.forward_units = 7;  // not read by this model
  AnchorState unused;  // the last_frame warp has no state
  const cv::Mat right = net.next(context, turn_right, unused);
  ASSERT_EQ(right.type(), CV_8UC3);
  ASSERT_EQ(right.size(), cv::Size(kWidth, kHeight));
  EXPECT_EQ(differences(right, shiftedByHand(newest, 2, 0)), 0.0);

  MotionStep left_and_down;  // yaw 3, pitch 1: dx = -3, dy = 1
  left_and_down.yaw_deg = 3;
  left_and_down.pitch_deg = 1;
  EXPECT_EQ(differences(net.next(context, left_and_down, unused), shiftedByHand(newest, -3, 1)), 0.0);

  // One unit of strafe: mask 0, the frame is the fill, i.e. the newest frame as the net
  // read it from its input planes (another frame or swapped channels would differ).
  MotionStep strafe;
  strafe.strafe_units = 1;
  strafe.yaw_deg = 5;
  EXPECT_EQ(differences(net.next(context, strafe, unused), newest), 0.0);
}

TEST(WorldModelNet, WrongContextIsAnErrorNamingTheModel) {
  WorldModelNet net(kShiftModel, kWidth, kHeight, kContext, WorldWarp::kLastFrame, 90);
  const auto errorOf = [&](const std::vector<cv::Mat>& context) {
    try {
      AnchorState unused;
      net.next(context, MotionStep{}, unused);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string three = errorOf({randomFrame(1), randomFrame(2), randomFrame(3)});
  EXPECT_NE(three.find(kShiftModel), std::string::npos) << three;
  EXPECT_NE(three.find("3 frames, expected 4"), std::string::npos) << three;
  const cv::Mat big(240, 320, CV_8UC3, cv::Scalar::all(0));
  const std::string sized = errorOf({randomFrame(1), randomFrame(2), randomFrame(3), big});
  EXPECT_NE(sized.find("frame 3 is a 320x240 CV_8UC3, expected a 128x96 CV_8UC3"), std::string::npos) << sized;
  const cv::Mat grey(kHeight, kWidth, CV_8UC1, cv::Scalar(0));
  EXPECT_NE(errorOf({grey, randomFrame(2), randomFrame(3), randomFrame(4)}).find("frame 0"), std::string::npos);
}

TEST(WorldModelNet, MissingFileIsAnErrorNamingIt) {
  const std::string path = "/nonexistent/world_model.onnx";
  const std::string error = loadError(path);
  EXPECT_EQ(error, path + ": world model file does not exist");
}

TEST(WorldModelNet, CorruptFileIsAnErrorNamingIt) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("valerant_corrupt_world_model_" + std::to_string(::getpid()) + ".onnx"))
                               .string();
  {
    std::ofstream out(path, std::ios::binary);
    for (int i = 0; i < 4096; ++i) out.put(static_cast<char>((i * 7919 + 13) % 256));
  }
  const std::string error = loadError(path);
  std::filesystem::remove(path);
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_NE(error.find("not an ONNX model"), std::string::npos) << error;
}

TEST(WorldModelNet, WrongOutputShapeIsAnErrorNamingTheFile) {
  const std::string path = std::string(VALERANT_SOURCE_DIR) + "/test/data/world_model_five_channels.onnx";
  const std::string error = loadError(path);
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_NE(error.find("[1,5,96,128]"), std::string::npos) << error;
  EXPECT_NE(error.find("expected [1,6,96,128]"), std::string::npos) << error;
}

TEST(WorldModelNet, ModelOfAnotherContextLengthIsAnErrorNamingTheFile) {
  // The shift model reads 16 input channels (K = 4); K = 2 feeds it 10.
  const std::string error = loadError(kShiftModel, 2);
  EXPECT_NE(error.find(kShiftModel), std::string::npos) << error;
  EXPECT_NE(error.find("[1,10,96,128]"), std::string::npos) << error;
  EXPECT_NE(error.find("2 context frames of 128x96"), std::string::npos) << error;
}
