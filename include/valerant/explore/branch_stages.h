#pragma once
// The per-frame stages of one branch (paper section 3.2-3.3), as small functions that
// the in-process pipeline and the ROS nodes (branch_slam, floor_estimator) both call:
// SLAM tracks a frame and hands out the keyframe cloud it made, if any; the branch's
// floor estimator (RF) updates on keyframes and is propagated to every other frame.
#include <Eigen/Geometry>
#include <optional>

#include "valerant/config/config.h"
#include "valerant/explore/floor_estimator.h"
#include "valerant/slam/slam.h"

namespace valerant {

struct TrackedStep {
  TrackedFrame frame;
  std::optional<KeyframeCloud> keyframe;  // set when this frame made a keyframe
};

TrackedStep trackStep(Slam& slam, const SlamInput& input);

// The floor of one frame: a fit on its keyframe cloud, else the current relation.
FloorPlane floorStep(FloorEstimator& floor, const TrackedFrame& frame, const KeyframeCloud* keyframe);

// The episode's floor estimator, made at the first tracked frame: before any floor is
// seen the vertical is that camera's up, -y of its optical frame.
FloorEstimator startFloorEstimator(const Config& config, const Eigen::Isometry3d& first_camera_to_map);

}  // namespace valerant
