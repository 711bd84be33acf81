#pragma once
// Dense depth of one frame by multi-view plane sweep: fronto-parallel planes of the
// reference camera, uniform in inverse depth from infinity to `near`, each inducing a
// homography from the reference to every source keyframe. Each source is first
// re-sampled with the reference's orientation, after which a plane's homography is a
// uniform scale about the epipole (cheap to sample). Planes are spaced about
// plane_step_px of disparity apart at the image border (fewer for short baselines).
// Images are shrunk and normalised by their local contrast (the engine's lightmapped
// walls are dark: raw grey differences would be tiny everywhere). The cost of a plane
// is the truncated absolute difference, summed over the sources and averaged over a
// square window; a plane is not scored where the window leaves a source. Each pixel
// takes the cheapest plane, refined to sub-plane precision by a parabola.
//
// Confidence (on the scale of the paper's 4.0 cut, which was MASt3R's): with c1 the best
// cost and c2 the best cost at least three planes away (the strongest rival depth),
//     confidence = 1 + gain * ln((c2 + noise) / (c1 + noise)),   capped at max_confidence.
// It is 1 when the cost curve is flat (no texture, no parallax near the epipole, no
// rival plane scored) and grows with how much better the chosen depth explains the
// images than any other. With the default gain 9 the 4.0 cut keeps pixels whose rival
// costs at least 1.4x the chosen depth (e^(3/9)). Calibrated on engine rollouts
// (oa_dm1, oa_dm4, aggressor; forward and turning), after one median scale per run:
// rival ratio 1.4-1.65 gave AbsRel 0.03-0.09, above 1.65 0.03-0.07, 1.2-1.4 0.08-0.37,
// and below 1.2 the depth was mostly wrong (0.4-1.6). Pixels whose best plane (with its
// sub-plane offset) is closer to infinity than params.min_plane, or that no plane
// scores, get NaN depth and confidence 0.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <vector>

#include "valerant/common/camera.h"
#include "valerant/config/visual_slam_config.h"
#include "valerant/slam/visual/sweep_kernels.h"

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
// params.simd picks the inner loops' instructions (sweep_kernels.h); both give the same bits.
SweepDepth planeSweep(const SweepView& reference, const std::vector<SweepView>& sources,
                      const CameraIntrinsics& k, double near, const PlaneSweepParams& params);

}  // namespace valerant::visual
