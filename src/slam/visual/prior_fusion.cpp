#include "valerant/slam/visual/prior_fusion.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "valerant/common/error.h"

namespace valerant::visual {
namespace {

void requireSameSize(const cv::Mat& a, const cv::Mat& b, const char* what) {
  if (a.size() != b.size() || a.type() != CV_32F || b.type() != CV_32F)
    throw InputError(what, "depth, confidence and prior must be CV_32F images of one size");
}

}  // namespace

std::optional<double> priorScale(const cv::Mat& sweep_depth, const cv::Mat& sweep_confidence, const cv::Mat& prior_m,
                                 const PriorFusionParams& params) {
  requireSameSize(sweep_depth, prior_m, "prior scale");
  requireSameSize(sweep_confidence, prior_m, "prior scale");
  std::vector<double> ratios;
  for (int r = 0; r < prior_m.rows; ++r)
    for (int c = 0; c < prior_m.cols; ++c) {
      const float d = sweep_depth.at<float>(r, c), p = prior_m.at<float>(r, c);
      if (std::isfinite(d) && d > 0 && sweep_confidence.at<float>(r, c) >= params.min_confidence && p > 0 &&
          p <= params.max_depth_m)
        ratios.push_back(d / p);
    }
  if (static_cast<int>(ratios.size()) < params.min_scale_pixels) return std::nullopt;
  auto mid = ratios.begin() + static_cast<long>(ratios.size() / 2);
  std::nth_element(ratios.begin(), mid, ratios.end());
  return *mid;
}

std::optional<double> priorMetresPerUnit(const std::vector<cv::Point2f>& pixels, const std::vector<double>& depths,
                                         const cv::Mat& prior_m, const PriorFusionParams& params, int min_points) {
  if (pixels.size() != depths.size())
    throw InputError("prior scale of triangulated points", "needs one depth per pixel");
  if (prior_m.type() != CV_32F) throw InputError("prior scale of triangulated points", "prior must be CV_32F");
  std::vector<double> ratios;
  for (size_t i = 0; i < pixels.size(); ++i) {
    const int c = static_cast<int>(std::lround(pixels[i].x)), r = static_cast<int>(std::lround(pixels[i].y));
    if (r < 0 || c < 0 || r >= prior_m.rows || c >= prior_m.cols || !(depths[i] > 0) || !std::isfinite(depths[i]))
      continue;
    const float p = prior_m.at<float>(r, c);
    if (p > 0 && p <= params.max_depth_m) ratios.push_back(p / depths[i]);
  }
  if (ratios.empty() || static_cast<int>(ratios.size()) < min_points) return std::nullopt;
  auto mid = ratios.begin() + static_cast<long>(ratios.size() / 2);
  std::nth_element(ratios.begin(), mid, ratios.end());
  return *mid;
}

void fusePrior(cv::Mat& depth, cv::Mat& confidence, const cv::Mat& prior_m, const cv::Mat& prior_log_scale,
               double map_per_metre, const PriorFusionParams& params) {
  requireSameSize(depth, prior_m, "prior fusion");
  requireSameSize(confidence, prior_m, "prior fusion");
  requireSameSize(prior_log_scale, prior_m, "prior fusion");
  if (!(map_per_metre > 0)) throw InputError("prior fusion scale", "must be positive");
  for (int r = 0; r < prior_m.rows; ++r)
    for (int c = 0; c < prior_m.cols; ++c) {
      const float p = prior_m.at<float>(r, c);
      if (!(p > 0) || p > params.max_depth_m) continue;
      const double conf = std::min(params.max_confidence,
                                   params.confidence_gain / std::exp(static_cast<double>(prior_log_scale.at<float>(r, c))));
      float& d = depth.at<float>(r, c);
      float& k = confidence.at<float>(r, c);
      if (std::isfinite(d) && k >= conf) continue;  // the sweep is at least as sure
      d = static_cast<float>(p * map_per_metre);
      k = static_cast<float>(conf);
    }
}

}  // namespace valerant::visual
