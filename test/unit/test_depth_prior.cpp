// The learned depth prior: an ONNX round trip through OpenCV DNN on a hand-made model
// (learn/make_test_depth_model.py: ln depth = ln 2 + R + 0.5 G + 0.25 B, ln b = -1 + 0.5 B),
// errors that name the file, concurrent predictions, and its configuration.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <future>
#include <unistd.h>

#include "valerant/common/error.h"
#include "valerant/config/config.h"
#include "valerant/common/depth_prior.h"
#include "valerant/slam/depth_prior_factory.h"

using namespace valerant;

namespace {

const std::string kLinearModel = std::string(VALERANT_SOURCE_DIR) + "/test/data/depth_prior_linear.onnx";
const cv::Size kNetSize(128, 96);

std::string loadError(const std::string& path, cv::Size net_size = kNetSize) {
  try {
    DepthPrior prior(path, net_size);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Every pixel of `m` (CV_32F) is within `tolerance` of `expected`.
void expectUniform(const cv::Mat& m, double expected, double tolerance) {
  double lo = 0, hi = 0;
  cv::minMaxLoc(m, &lo, &hi);
  EXPECT_NEAR(lo, expected, tolerance);
  EXPECT_NEAR(hi, expected, tolerance);
}

}  // namespace

TEST(DepthPrior, LinearModelGivesHandComputedDepthAndScale) {
  const DepthPrior prior(kLinearModel, kNetSize);
  // R = 1 only: ln depth = ln 2 + 1, depth = 2e; ln b = -1.
  const DepthPrediction red = prior.predict(cv::Mat(240, 320, CV_8UC3, cv::Scalar(255, 0, 0)));
  ASSERT_EQ(red.depth_m.type(), CV_32F);
  ASSERT_EQ(red.log_scale.type(), CV_32F);
  EXPECT_EQ(red.depth_m.size(), kNetSize);
  EXPECT_EQ(red.log_scale.size(), kNetSize);
  expectUniform(red.depth_m, 2.0 * std::exp(1.0), 1e-4);  // 5.43656 m
  expectUniform(red.log_scale, -1.0, 1e-6);
  // R = 1, G = 0.4, B = 0.2: ln depth = ln 2 + 1.25, ln b = -0.9. Swapped channels (BGR)
  // would give ln 2 + 0.65 and ln b = -0.5.
  const DepthPrediction mixed = prior.predict(cv::Mat(240, 320, CV_8UC3, cv::Scalar(255, 102, 51)));
  expectUniform(mixed.depth_m, 2.0 * std::exp(1.25), 1e-4);  // 6.98069 m
  expectUniform(mixed.log_scale, -0.9, 1e-6);
}

TEST(DepthPrior, ResizedToTheCameraIsBilinear) {
  const DepthPrior prior(kLinearModel, kNetSize);
  // Left half black (depth 2 m), right half red (2e m).
  cv::Mat frame(240, 320, CV_8UC3, cv::Scalar(0, 0, 0));
  frame.colRange(160, 320).setTo(cv::Scalar(255, 0, 0));
  const DepthPrediction net = prior.predict(frame);
  const DepthPrediction camera = net.resized(cv::Size(320, 240));
  EXPECT_EQ(camera.depth_m.size(), cv::Size(320, 240));
  EXPECT_EQ(camera.log_scale.size(), cv::Size(320, 240));
  EXPECT_NEAR(camera.depth_m.at<float>(120, 10), 2.0, 1e-4);
  EXPECT_NEAR(camera.depth_m.at<float>(120, 310), 2.0 * std::exp(1.0), 1e-4);
  // Net column 63 (2 m) and 64 (2e m) straddle camera column 159.5: bilinear gives
  // their mean halfway between.
  const float across = 0.5f * (camera.depth_m.at<float>(120, 159) + camera.depth_m.at<float>(120, 160));
  EXPECT_NEAR(across, 0.5 * (2.0 + 2.0 * std::exp(1.0)), 1e-3);
  expectUniform(camera.log_scale, -1.0, 1e-6);
}

TEST(DepthPrior, ANetReadingTwiceItsOutputSizePredictsAtItsOutput) {
  // The same linear model at stride 2: 256 x 192 in, 128 x 96 out.
  const DepthPrior prior(std::string(VALERANT_SOURCE_DIR) + "/test/data/depth_prior_linear_x2.onnx",
                         cv::Size(256, 192));
  EXPECT_EQ(prior.netSize(), cv::Size(256, 192));
  EXPECT_EQ(prior.outputSize(), kNetSize);
  // R = 1, G = 0.4, B = 0.2, as above: ln depth = ln 2 + 1.25, ln b = -0.9.
  const DepthPrediction mixed = prior.predict(cv::Mat(240, 320, CV_8UC3, cv::Scalar(255, 102, 51)));
  EXPECT_EQ(mixed.depth_m.size(), kNetSize);
  EXPECT_EQ(mixed.log_scale.size(), kNetSize);
  expectUniform(mixed.depth_m, 2.0 * std::exp(1.25), 1e-4);
  expectUniform(mixed.log_scale, -0.9, 1e-6);
}

TEST(DepthPrior, RejectsAFrameThatIsNotRgb8) {
  const DepthPrior prior(kLinearModel, kNetSize);
  try {
    prior.predict(cv::Mat(240, 320, CV_8UC1, cv::Scalar(0)));
    FAIL() << "a grey frame was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("CV_8UC3"), std::string::npos) << e.what();
  }
}

TEST(DepthPrior, MissingFileIsAnErrorNamingIt) {
  const std::string path = std::string(VALERANT_SOURCE_DIR) + "/test/data/no_such_model.onnx";
  const std::string error = loadError(path);
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_NE(error.find("does not exist"), std::string::npos) << error;
}

TEST(DepthPrior, CorruptFileIsAnErrorNamingIt) {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("valerant_corrupt_" + std::to_string(::getpid()) + ".onnx")).string();
  {
    std::ofstream out(path, std::ios::binary);
    for (int i = 0; i < 4096; ++i) out.put(static_cast<char>((i * 7919 + 13) % 256));
  }
  const std::string error = loadError(path);
  std::filesystem::remove(path);
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_NE(error.find("not an ONNX model"), std::string::npos) << error;
}

TEST(DepthPrior, WrongOutputShapeIsAnErrorNamingTheFile) {
  const std::string path = std::string(VALERANT_SOURCE_DIR) + "/test/data/depth_prior_one_channel.onnx";
  const std::string error = loadError(path);
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_NE(error.find("[1,1,96,128]"), std::string::npos) << error;
  EXPECT_NE(error.find("expected [1,2,96,128]"), std::string::npos) << error;
}

TEST(DepthPrior, ConcurrentPredictionsEqualOneThreads) {
  const DepthPrior prior(kLinearModel, kNetSize);
  cv::Mat frame(240, 320, CV_8UC3);
  cv::RNG(7).fill(frame, cv::RNG::UNIFORM, 0, 256);
  const DepthPrediction alone = prior.predict(frame);

  constexpr int kThreads = 4, kCalls = 5;
  std::promise<void> start;
  const std::shared_future<void> go = start.get_future().share();
  std::vector<std::future<std::vector<DepthPrediction>>> results;
  for (int t = 0; t < kThreads; ++t) {
    results.push_back(std::async(std::launch::async, [&prior, &frame, go] {
      go.wait();  // all threads call predict at the same time
      std::vector<DepthPrediction> out;
      for (int i = 0; i < kCalls; ++i) out.push_back(prior.predict(frame));
      return out;
    }));
  }
  start.set_value();
  for (auto& r : results) {
    for (const DepthPrediction& p : r.get()) {
      EXPECT_EQ(cv::norm(p.depth_m, alone.depth_m, cv::NORM_INF), 0.0);
      EXPECT_EQ(cv::norm(p.log_scale, alone.log_scale, cv::NORM_INF), 0.0);
    }
  }
}

TEST(DepthPriorConfig, DefaultIsTheShippedPriorAndThePaperHasNone) {
  const Config shipped = loadConfig(std::string(VALERANT_SOURCE_DIR) + "/config/valerant.yaml");
  EXPECT_EQ(shipped.slam.depth_prior, "learned");
  EXPECT_EQ(shipped.slam.depth_prior_model, "models/depth_prior.onnx");
  EXPECT_EQ(shipped.slam.depth_prior_width, 128);
  EXPECT_EQ(shipped.slam.depth_prior_height, 96);
  // The shipped model loads from the source tree and answers a camera frame.
  SlamConfig in_source = shipped.slam;
  in_source.depth_prior_model = std::string(VALERANT_SOURCE_DIR) + "/models/depth_prior.onnx";
  const auto prior = loadDepthPrior(in_source);
  ASSERT_NE(prior, nullptr);
  const DepthPrediction p = prior->predict(cv::Mat(240, 320, CV_8UC3, cv::Scalar(90, 100, 110)));
  EXPECT_EQ(p.depth_m.size(), cv::Size(128, 96));  // the net's size; resized() gives the camera's
  EXPECT_GT(cv::mean(p.depth_m)[0], 0.1);
  const Config paper = loadConfig(std::string(VALERANT_SOURCE_DIR) + "/config/paper.yaml");
  EXPECT_EQ(paper.slam.depth_prior, "none");
  EXPECT_EQ(loadDepthPrior(paper.slam), nullptr);
}

TEST(DepthPriorConfig, UnknownValueIsAnErrorNamingTheKey) {
  try {
    parseConfig("extends: " + std::string(VALERANT_SOURCE_DIR) + "/config/valerant.yaml\nslam:\n  depth_prior: bogus\n",
                "test.yaml");
    FAIL() << "depth_prior: bogus was accepted";
  } catch (const InputError& e) {
    const std::string error = e.what();
    EXPECT_NE(error.find("test.yaml"), std::string::npos) << error;
    EXPECT_NE(error.find("slam.depth_prior"), std::string::npos) << error;
    EXPECT_NE(error.find("bogus"), std::string::npos) << error;
  }
}

TEST(DepthPriorConfig, LearnedLoadsTheModelRelativeToThePackageFolder) {
  const Config c = parseConfig(
      "extends: " + std::string(VALERANT_SOURCE_DIR) +
          "/config/valerant.yaml\nslam:\n  depth_prior: learned\n  depth_prior_model: test/data/depth_prior_linear.onnx\n", "test.yaml");
  const auto prior = loadDepthPrior(c.slam);
  ASSERT_NE(prior, nullptr);
  EXPECT_EQ(prior->modelPath(), kLinearModel);
  EXPECT_EQ(prior->netSize(), kNetSize);
}
