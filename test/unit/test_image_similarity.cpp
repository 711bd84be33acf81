// PSNR and SSIM (eval/image_similarity.h) on tiny images worked out by hand. SSIM's
// window is 11 x 11, so an 11 x 11 image has exactly one window, centred on pixel
// (5, 5); its 1-D Gaussian weights are exp(-k^2 / 4.5) / S for k = -5..5, S = 3.759234,
// the centre weight g0 = 1 / S = 0.266012.
#include <gtest/gtest.h>

#include "valerant/common/error.h"
#include "valerant/eval/image_similarity.h"

using namespace valerant;

namespace {

constexpr double kC1 = 6.5025, kC2 = 58.5225;  // (0.01 * 255)^2, (0.03 * 255)^2

cv::Mat constant(int size, uchar r, uchar g, uchar b) { return cv::Mat(size, size, CV_8UC3, cv::Scalar(r, g, b)); }

// 11 x 11, every channel `centre` + `step` * sign(x - 5): left columns one side, the
// middle column `centre`, right columns the other side.
cv::Mat stripes(int centre, int step) {
  cv::Mat m(11, 11, CV_8UC3);
  for (int y = 0; y < 11; ++y)
    for (int x = 0; x < 11; ++x) {
      const int v = centre + step * ((x > 5) - (x < 5));
      m.at<cv::Vec3b>(y, x) = cv::Vec3b(v, v, v);
    }
  return m;
}

}  // namespace

TEST(ImageSimilarity, PsnrOfOneChannelOfOnePixel) {
  // 2 x 2 x 3 = 12 values, one off by 10: MSE = 100 / 12, PSNR = 10 log10(65025 * 12 / 100) = 38.92262 dB.
  const cv::Mat a = constant(2, 0, 0, 0);
  cv::Mat b = a.clone();
  b.at<cv::Vec3b>(1, 0)[2] = 10;
  EXPECT_NEAR(psnrDb(a, b), 38.92262, 1e-4);
  EXPECT_NEAR(psnrDb(b, a), 38.92262, 1e-4);
}

TEST(ImageSimilarity, PsnrOfBlackAgainstWhiteIsZeroAndOfIdenticalImagesTheCap) {
  EXPECT_NEAR(psnrDb(constant(3, 0, 0, 0), constant(3, 255, 255, 255)), 0.0, 1e-12);
  EXPECT_EQ(psnrDb(constant(3, 7, 8, 9), constant(3, 7, 8, 9)), kMaxPsnrDb);
}

TEST(ImageSimilarity, SsimOfIdenticalImagesIsOne) {
  const cv::Mat a = stripes(100, 40);
  EXPECT_NEAR(ssim(a, a), 1.0, 1e-12);
}

TEST(ImageSimilarity, SsimOfTwoConstantImagesIsTheLuminanceTerm) {
  // No variance: SSIM = (2 * 100 * 50 + C1) / (100^2 + 50^2 + C1) = 10006.5025 / 12506.5025.
  EXPECT_NEAR(ssim(constant(11, 100, 100, 100), constant(11, 50, 50, 50)), 0.8001040, 1e-6);
  // A larger image: every window gives the same.
  EXPECT_NEAR(ssim(constant(20, 100, 100, 100), constant(20, 50, 50, 50)), 0.8001040, 1e-6);
}

TEST(ImageSimilarity, SsimOfMirroredStripesIsTheNegativeStructureTerm) {
  // a = 100 + 40 s, b = 100 - 40 s, s = sign(x - 5): both window means are 100 (s is odd
  // about the centre column), both variances 1600 (1 - g0) = 1174.3812 (s^2 = 1 but in
  // the centre column), the covariance minus that. SSIM = 1 * (C2 - 2 * 1174.3812) /
  // (C2 + 2 * 1174.3812) = -0.951379.
  EXPECT_NEAR(ssim(stripes(100, 40), stripes(100, -40)), -0.951379, 1e-5);
  EXPECT_NEAR(ssim(stripes(100, -40), stripes(100, 40)), -0.951379, 1e-5);
}

TEST(ImageSimilarity, SsimAveragesTheThreeChannels) {
  // R equal (1), G and B 100 against 50 (0.8001040 each): (1 + 2 * 0.8001040) / 3.
  EXPECT_NEAR(ssim(constant(11, 30, 100, 100), constant(11, 30, 50, 50)), 0.8667360, 1e-6);
}

TEST(ImageSimilarity, WrongImagesAreErrorsNamingThem) {
  EXPECT_THROW(psnrDb(constant(3, 0, 0, 0), constant(4, 0, 0, 0)), InputError);
  EXPECT_THROW(psnrDb(cv::Mat(), cv::Mat()), InputError);
  EXPECT_THROW(psnrDb(cv::Mat(3, 3, CV_8UC1, cv::Scalar(0)), cv::Mat(3, 3, CV_8UC1, cv::Scalar(0))), InputError);
  try {
    ssim(constant(10, 0, 0, 0), constant(10, 0, 0, 0));  // smaller than the window
    FAIL() << "a 10 x 10 image has no SSIM window";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("SSIM images"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("at least 11x11"), std::string::npos) << e.what();
  }
}
