#pragma once
// One frame's metric depth estimate against the engine's true depth, as the depth
// prior's benchmarks score it (learn/valerant_learn/metrics.py's protocol without its
// clamp of predictions): over the pixels whose true depth is in [0.1, 80] m (sky, NaN,
// is left out) and whose estimate is a positive finite depth.
#include <opencv2/core.hpp>
#include <optional>

namespace valerant {

constexpr float kMinScoredDepthM = 0.1f, kMaxScoredDepthM = 80.0f;

// True depth `g` (metres) that the scores count: in [0.1, 80] m, false for NaN.
bool scoredTruthDepth(float g);

struct MetricDepthScore {
  double abs_rel = 0;  // mean |p - g| / g
  double delta1 = 0;   // share of pixels with max(p / g, g / p) < 1.25
  long pixels = 0;
};

// `estimate` (CV_32F, NaN or <= 0 = none) times `scale` as p, against `truth` (CV_32F
// metres) as g; nothing when no pixel counts. Throws InputError for images that are
// not both CV_32F of one size.
std::optional<MetricDepthScore> scoreMetricDepth(const cv::Mat& estimate, const cv::Mat& truth, double scale = 1.0);

}  // namespace valerant
