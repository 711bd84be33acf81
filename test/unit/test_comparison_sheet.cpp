// The comparison sheet's layout (common/comparison_sheet.h): a 22 px header, a 44 px
// label column, per cell truth above generated with 4 px gaps, missing frames grey.
#include <gtest/gtest.h>

#include "valerant/common/comparison_sheet.h"
#include "valerant/common/error.h"

using namespace valerant;

TEST(ComparisonSheet, TruthAboveGeneratedAndMissingFramesGrey) {
  const cv::Mat red(48, 64, CV_8UC3, cv::Scalar(200, 0, 0)), blue(48, 64, CV_8UC3, cv::Scalar(0, 0, 200));
  const std::vector<ComparisonRow> rows = {{"uw", {red, red}, {blue, blue}}, {"jq", {red, cv::Mat()}, {blue, cv::Mat()}}};
  const cv::Mat sheet = makeComparisonSheet(rows, {"frame 8", "frame 97"});
  ASSERT_EQ(sheet.type(), CV_8UC3);
  EXPECT_EQ(sheet.cols, 44 + 2 * (64 + 4));
  EXPECT_EQ(sheet.rows, 22 + 2 * (2 * 48 + 4));
  // Bottom-right pixels of tiles (away from their labels): row 0 column 1 truth, then model.
  EXPECT_EQ(sheet.at<cv::Vec3b>(22 + 47, 44 + 68 + 63), cv::Vec3b(200, 0, 0));
  EXPECT_EQ(sheet.at<cv::Vec3b>(22 + 95, 44 + 68 + 63), cv::Vec3b(0, 0, 200));
  // Row 1 column 1 has no frame.
  EXPECT_EQ(sheet.at<cv::Vec3b>(22 + 100 + 47, 44 + 68 + 63), cv::Vec3b(96, 96, 96));
}

TEST(ComparisonSheet, MismatchedRowsAndFramesAreErrors) {
  const cv::Mat f(12, 16, CV_8UC3, cv::Scalar::all(1));
  EXPECT_THROW(makeComparisonSheet({{"uw", {f}, {f}}}, {"a", "b"}), InputError);
  EXPECT_THROW(makeComparisonSheet({{"uw", {f}, {cv::Mat(12, 17, CV_8UC3)}}}, {"a"}), InputError);
  EXPECT_THROW(makeComparisonSheet({{"uw", {cv::Mat()}, {cv::Mat()}}}, {"a"}), InputError);
}
