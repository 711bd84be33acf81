#include "valerant/eval/metric_depth_score.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "valerant/common/error.h"

namespace valerant {

bool scoredTruthDepth(float g) { return g >= kMinScoredDepthM && g <= kMaxScoredDepthM; }

std::optional<MetricDepthScore> scoreMetricDepth(const cv::Mat& estimate, const cv::Mat& truth, double scale) {
  if (estimate.type() != CV_32F || truth.type() != CV_32F || estimate.size() != truth.size())
    throw InputError("depth images", "need two CV_32F images of one size, got " + std::to_string(estimate.cols) +
                                         "x" + std::to_string(estimate.rows) + " " +
                                         cv::typeToString(estimate.type()) + " and " + std::to_string(truth.cols) +
                                         "x" + std::to_string(truth.rows) + " " + cv::typeToString(truth.type()));
  double abs_rel = 0, within = 0;
  long pixels = 0;
  for (int y = 0; y < truth.rows; ++y) {
    for (int x = 0; x < truth.cols; ++x) {
      const float g = truth.at<float>(y, x), e = estimate.at<float>(y, x);
      if (!scoredTruthDepth(g) || !std::isfinite(e) || e <= 0) continue;
      const double p = scale * e;
      abs_rel += std::abs(p - g) / g;
      within += std::max(p / g, g / p) < 1.25 ? 1 : 0;
      ++pixels;
    }
  }
  if (pixels == 0) return std::nullopt;
  return MetricDepthScore{abs_rel / pixels, within / pixels, pixels};
}

}  // namespace valerant
