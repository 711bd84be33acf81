// The sweep's window mean (box_mean.h): a hand-worked case on both paths, and both paths
// equal to cv::boxFilter bit for bit on random images (odd widths included), so the
// sweep's costs did not change when it replaced OpenCV's filter.
#include <gtest/gtest.h>

#include <cstring>
#include <opencv2/imgproc.hpp>
#include <random>

#include "valerant/common/error.h"
#include "valerant/slam/visual/box_mean.h"

using namespace valerant;
using namespace valerant::visual;

namespace {

bool sameBits(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() &&
         std::memcmp(a.ptr(), b.ptr(), a.total() * a.elemSize()) == 0;
}

}  // namespace

TEST(BoxMean, ThreeByThreeByHand) {
  // 1 2 3
  // 4 5 6   with borders replicated, window 3:
  // 7 8 9
  // centre (1,1): the mean of 1..9 = 5; corner (0,0): rows 1 1 2 / 1 1 2 / 4 4 5 = 21 / 9;
  // (0,2): 2 3 3 / 2 3 3 / 5 6 6 = 33 / 9; (2,1): 4 5 6 / 7 8 9 / 7 8 9 = 63 / 9 = 7.
  cv::Mat image = (cv::Mat_<float>(3, 3) << 1, 2, 3, 4, 5, 6, 7, 8, 9);
  for (SweepIsa isa : sweepIsasHere()) {
    cv::Mat mean;
    BoxMean(3, isa).apply(image, mean);
    EXPECT_FLOAT_EQ(mean.at<float>(1, 1), 5.0f);
    EXPECT_FLOAT_EQ(mean.at<float>(0, 0), 21.0f / 9);
    EXPECT_FLOAT_EQ(mean.at<float>(0, 2), 33.0f / 9);
    EXPECT_FLOAT_EQ(mean.at<float>(2, 1), 7.0f);
  }
}

TEST(BoxMean, EqualsOpenCvsBoxFilterBitForBit) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> cost(0, 40);
  for (int window : {3, 5, 7}) {
    for (const cv::Size size : {cv::Size(160, 120), cv::Size(37, 11), cv::Size(5, 6), cv::Size(1, 3)}) {
      cv::Mat image(size, CV_32F);
      for (int i = 0; i < image.rows * image.cols; ++i) image.ptr<float>(0)[i] = cost(rng);
      image.at<float>(0, 0) = 1e6f;  // a large value, as an invalid sample's cost
      cv::Mat expected;
      cv::boxFilter(image, expected, CV_32F, cv::Size(window, window), cv::Point(-1, -1), true, cv::BORDER_REPLICATE);
      for (SweepIsa isa : sweepIsasHere()) {
        cv::Mat mean;
        BoxMean(window, isa).apply(image, mean);
        EXPECT_TRUE(sameBits(mean, expected))
            << "window " << window << ", " << size << ", isa " << static_cast<int>(isa);
      }
    }
  }
}

TEST(BoxMean, AnEvenWindowOrAnotherImageTypeIsAnError) {
  EXPECT_THROW(BoxMean(4), InputError);
  cv::Mat bytes(4, 4, CV_8U, cv::Scalar(1)), out;
  EXPECT_THROW(BoxMean(3).apply(bytes, out), InputError);
}
