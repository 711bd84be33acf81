#include "valerant/explore/branch_stages.h"

namespace valerant {

TrackedStep trackStep(Slam& slam, const SlamInput& input) {
  TrackedStep step{slam.track(input), std::nullopt};
  if (step.frame.keyframe && slam.keyframeCount() > 0)
    step.keyframe = slam.keyframeClouds(slam.keyframeCount() - 1).front();
  return step;
}

FloorPlane floorStep(FloorEstimator& floor, const TrackedFrame& frame, const KeyframeCloud* keyframe) {
  return keyframe ? floor.update(keyframe->points, frame.camera_to_map) : floor.at(frame.camera_to_map);
}

FloorEstimator startFloorEstimator(const Config& config, const Eigen::Isometry3d& first_camera_to_map) {
  return FloorEstimator(config.floor, -first_camera_to_map.linear().col(1), config.collision.min_confidence,
                        config.world.seed);
}

}  // namespace valerant
