// One frame's metric depth score (eval/metric_depth_score.h), worked by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "valerant/common/error.h"
#include "valerant/eval/metric_depth_score.h"

using namespace valerant;

TEST(MetricDepthScore, CountsPixelsWithTruthInRangeAndAnEstimate) {
  const float nan = std::nanf("");
  // Truth 1, 2, NaN (sky), 100 (beyond 80 m), 4, 0.05 (nearer than 0.1 m).
  const cv::Mat truth = (cv::Mat_<float>(2, 3) << 1, 2, nan, 100, 4, 0.05f);
  // Estimates 1.5, 2, 3, 1, NaN (none), 1.
  const cv::Mat estimate = (cv::Mat_<float>(2, 3) << 1.5f, 2, 3, 1, nan, 1);
  // Counted: (1.5 vs 1) |0.5| / 1, ratio 1.5; (2 vs 2) 0, ratio 1. AbsRel 0.25, delta1 1/2.
  const auto s = scoreMetricDepth(estimate, truth);
  ASSERT_TRUE(s.has_value());
  EXPECT_NEAR(s->abs_rel, 0.25, 1e-12);
  EXPECT_NEAR(s->delta1, 0.5, 1e-12);
  EXPECT_EQ(s->pixels, 2);
  // Scaled by 2: (3 vs 1) 2, (4 vs 2) 1: AbsRel 1.5, no ratio under 1.25.
  const auto scaled = scoreMetricDepth(estimate, truth, 2.0);
  EXPECT_NEAR(scaled->abs_rel, 1.5, 1e-12);
  EXPECT_NEAR(scaled->delta1, 0.0, 1e-12);
}

TEST(MetricDepthScore, NothingToScoreAndWrongImages) {
  const cv::Mat sky(2, 2, CV_32F, cv::Scalar(std::nanf("")));
  EXPECT_FALSE(scoreMetricDepth(cv::Mat(2, 2, CV_32F, cv::Scalar(1)), sky).has_value());
  const cv::Mat zero_estimate(2, 2, CV_32F, cv::Scalar(0));
  EXPECT_FALSE(scoreMetricDepth(zero_estimate, cv::Mat(2, 2, CV_32F, cv::Scalar(1))).has_value());
  EXPECT_THROW(scoreMetricDepth(cv::Mat(2, 2, CV_32F), cv::Mat(2, 3, CV_32F)), InputError);
  EXPECT_THROW(scoreMetricDepth(cv::Mat(2, 2, CV_64F), cv::Mat(2, 2, CV_32F)), InputError);
}
