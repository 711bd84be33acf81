#pragma once
// Dense depth of one frame by multi-view plane sweep: fronto-parallel planes of the
// reference camera, uniform in inverse depth from infinity to `near`, each inducing a
// homography that warps every source keyframe onto the reference. Planes are spaced
// about plane_step_px of disparity apart at the image border (fewer for short
// baselines). Images are first shrunk and normalised by their local contrast (the
// engine's lightmapped walls are dark: raw grey differences would be tiny everywhere).
// The cost of a plane is the truncated absolute difference, averaged over the sources
// and a square window; each pixel takes the cheapest plane, refined to sub-plane
// precision by a parabola through its neighbours.
//
// Confidence (the scale of the paper's 4.0 cut, which was MASt3R's): with c1 the best
// cost and c2 the best cost at least three planes away (the strongest rival depth),
//     confidence = 1 + gain * ln((c2 + noise) / (c1 + noise)),   capped at max_confidence.
// It is 1 when the cost curve is flat (no texture, no parallax near the epipole, the
// pixel leaves every source) and grows with how much better the chosen depth explains
// the images than any other. With the default gain, the 4.0 cut keeps pixels whose
// rival depth costs at least CUT_RATIO times the chosen one: the depth is then
// unambiguous and, on the engine rollouts, its error small. Pixels whose best plane is
// the one at infinity get NaN depth and confidence 0.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <vector>

#include "valerant/common/camera.h"
#include "valerant/slam/visual/visual_slam_params.h"

namespace valerant::visual {

struct SweepView {
  cv::Mat image;  // from sweepImage()
  Eigen::Isometry3d camera_to_map = Eigen::Isometry3d::Identity();
};

struct SweepDepth {
  cv::Mat depth;       // CV_32F, sweep resolution, along the optical axis, NaN = unknown
  cv::Mat confidence;  // CV_32F, 0 where depth is unknown
};

// A grey CV_8U frame shrunk by params.downsample (pixel-area averaging) and normalised
// to zero local mean and unit local contrast, CV_32F.
cv::Mat sweepImage(const cv::Mat& grey, const PlaneSweepParams& params);

// `k`: intrinsics at sweep resolution. Throws InputError for no source or near <= 0.
SweepDepth planeSweep(const SweepView& reference, const std::vector<SweepView>& sources,
                      const CameraIntrinsics& k, double near, const PlaneSweepParams& params);

}  // namespace valerant::visual
