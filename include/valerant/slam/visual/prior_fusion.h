#pragma once
// How the visual SLAM uses the learned depth prior (depth_prior.h). Triangulation is
// blind where exploration needs sight: turning in place (no parallax), at start-up
// (one standing frame), on sky and flat walls. The prior is metric and per frame, the
// plane sweep in map units and only where it has parallax; fusing them per pixel:
//   1. Scale: map units per metre = median over pixels where the sweep is confident
//      (>= min_confidence) of sweep depth / prior depth; with too few such pixels the
//      last scale is kept (the SLAM's map scale changes slowly).
//   2. Confidence of a prior pixel = gain / b, b the predicted Laplace scale of its ln
//      depth error (b = 0.15, about 15 % expected error, gives 4.0 at gain 0.6: the
//      paper's cut), capped at max_confidence. Pixels beyond max_depth_m (sky is
//      trained as 80 m) get none.
//   3. Per pixel the more confident estimate wins; both are then in map units.
//   4. A new triangulation (the first two-view map, or one after tracking was lost)
//      has a free scale: the prior at its points' pixels puts it in metres, so the map
//      keeps the scale the prior gave it at start-up (priorMetresPerUnit).
// The parameters are slam.visual.prior of the configuration (PriorFusionParams).
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "valerant/config/visual_slam_config.h"

namespace valerant::visual {

// Map units per metre from the pixels where both exist, or nullopt with too few.
std::optional<double> priorScale(const cv::Mat& sweep_depth, const cv::Mat& sweep_confidence, const cv::Mat& prior_m,
                                 const PriorFusionParams& params);

// Metres per unit of `depths`, the z-depths of points seen at `pixels` of the frame the
// prior `prior_m` was predicted for: the median of prior / depth over the points whose
// pixel is inside the image with a prior depth in (0, max_depth_m]; nullopt with fewer
// than `min_points` of them.
std::optional<double> priorMetresPerUnit(const std::vector<cv::Point2f>& pixels, const std::vector<double>& depths,
                                         const cv::Mat& prior_m, const PriorFusionParams& params, int min_points);

// Fuses in place: `depth` (map units, NaN = unknown) and `confidence` take the prior's
// value, times `map_per_metre`, wherever it is more confident. All CV_32F, one size.
void fusePrior(cv::Mat& depth, cv::Mat& confidence, const cv::Mat& prior_m, const cv::Mat& prior_log_scale,
               double map_per_metre, const PriorFusionParams& params);

}  // namespace valerant::visual
