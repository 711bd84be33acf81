#include "valerant/explore/branch_check.h"

#include <cmath>

namespace valerant {

BranchCheck::BranchCheck(const Config& config)
    : config_(config.collision), d_fwd_normalised_(config.world.d_fwd_units / config.world.eye_height_units) {}

void BranchCheck::add(const TrackedFrame& frame, const KeyframeCloud* keyframe, const FloorPlane& floor) {
  if (frame.state == TrackingState::kLost) lost_ = true;
  if (keyframe)
    for (const auto& p : keyframe->points)
      points_.push_back({p.position.cast<double>(), floor.normalisedHeight(p.position.cast<double>()), p.confidence});
  samples_.push_back(floor);
  const double central = frame.depth.empty() ? std::nan("") : centralMeanDepth(frame.depth, config_.center_fraction);
  depth_samples_.push_back({central, floor, frame.camera_to_map.linear().col(2)});
}

BranchVerdict BranchCheck::finish(const std::string& candidate, bool rotation_only) const {
  BranchVerdict v;
  v.candidate = candidate;
  v.rotation_only = rotation_only;
  v.slam_lost = lost_;
  if (config_.pointcloud_enabled) {
    const PointCloudCollision pc = detectPointCloudCollision(points_, samples_, config_, rotation_only);
    v.collision_pc = pc.collision;
    v.occupied_max = pc.occupied_max;
  }
  const DepthCollision dc = detectDepthCollision(depth_samples_, config_, d_fwd_normalised_);
  v.min_near_ratio = dc.min_near_ratio;
  if (config_.depth_enabled) v.collision_depth = dc.collision;
  return v;
}

}  // namespace valerant
