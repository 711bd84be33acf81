#pragma once
// Geometric quality of a fused map against the BSP surfaces (engine world only):
//  - accuracy: distance from every map point to the nearest surface sample (median and
//    90th percentile, metres). Samples are dense (see samples_per_m2), so this is the
//    point-to-surface distance up to half the sample spacing.
//  - completeness: of the surface samples the committed cameras saw (a sample is seen
//    when it projects into a committed frame and the ground-truth depth there agrees
//    with its own depth), the share with a map point within `within_m`. NaN (not
//    measured, written as null) when no committed frame carries its depth truth: the
//    graph's explorer gets truth poses without depth, to keep the rollout results small.
// Map points must already be in the BSP frame, in metres.
#include <Eigen/Core>
#include <vector>

#include "valerant/common/camera.h"
#include "valerant/explore/kept_truth.h"
#include "valerant/world/quake3/surface_samples.h"
#include "valerant/world/world_model.h"

namespace valerant {

struct MapAccuracy {
  int map_points = 0;
  double median_m = 0, p90_m = 0;
  int seen_samples = 0;
  double completeness_percent = 0;
};

struct MapAccuracyParams {
  double within_m = 0.25;
  // Test visibility in every 8th committed frame: the frames whose depth an episode keeps.
  int frame_stride = static_cast<int>(kCommittedDepthStride);
  double depth_agreement = 0.05;   // seen: |truth depth - sample depth| <= 5% of depth
};

MapAccuracy mapAccuracy(const std::vector<Eigen::Vector3d>& map_points_m,
                        const std::vector<quake3::SurfaceSample>& samples_units,
                        const std::vector<FrameTruth>& committed, const CameraIntrinsics& k,
                        const MapAccuracyParams& params = {});

}  // namespace valerant
