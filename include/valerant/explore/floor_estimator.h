#pragma once
// Robust floor estimation, RF (paper section 3.3.1, appendix A). Per keyframe: take the
// lower envelope of its points along the current vertical, fit the dominant plane by
// RANSAC, accept it only with >= min_support inliers and |n . e_y| >= 0.7. Otherwise
// propagate the most recent reliable camera-to-floor relation (normal and distance in
// the camera frame) to the new camera pose, instead of falling back to the first
// calibration.
//
// Continuity ([ours], floor.max_distance_change): the eye height is fixed and the SLAM
// scale drifts little between keyframes, so a fit whose camera-to-floor distance jumps
// by more than that factor from the last reliable one is a ledge, a step or a table
// top in the lower envelope (a camera closing in on a wall sees no floor left in front
// of it), and is treated as unreliable. floor.relock_keyframes such fits in a row that
// agree with each other are taken as the floor after all (the SLAM re-scaled, or the
// first floor was the wrong one).
//
// With RF off (the paper's ablation) the first accepted plane is kept in the map frame
// for the whole episode.
//
// A value type: copy it to branch, assign it to restore.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/geometry/floor_plane.h"
#include "valerant/slam/slam.h"

namespace valerant {

class FloorEstimator {
 public:
  // `initial_up`: the vertical in the map frame before any floor is seen (for a SLAM
  // map, the first camera's up = -y of its optical frame).
  FloorEstimator(const FloorConfig& config, const Eigen::Vector3d& initial_up, double min_confidence,
                 uint32_t seed = 0);

  // Estimates the floor of one keyframe.
  FloorPlane update(const std::vector<CloudPoint>& points, const Eigen::Isometry3d& camera_to_map);
  // The floor at any pose from the current relation (for non-keyframe samples);
  // `known` is false until a floor has been accepted.
  FloorPlane at(const Eigen::Isometry3d& camera_to_map) const;

  bool hasReliable() const { return has_relation_; }
  const Eigen::Vector3d& up() const { return up_; }

 private:
  struct Fit {
    Eigen::Vector3d q = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::UnitZ();
    int support = 0;
  };
  Fit fitLowerEnvelope(const std::vector<CloudPoint>& points, const Eigen::Vector3d& c);
  // Whether a fit at `distance` from the camera continues the floor (see above).
  bool continuesFloor(double distance);

  FloorConfig config_;
  double min_confidence_;
  Eigen::Vector3d up_;
  uint64_t updates_ = 0;  // seeds each keyframe's RANSAC deterministically
  uint32_t seed_;
  // Camera-to-floor relation of the last reliable keyframe, in its camera frame.
  bool has_relation_ = false;
  Eigen::Vector3d relation_normal_camera_ = Eigen::Vector3d(0, -1, 0);
  double relation_distance_ = 1.0;
  // Fits in a row that jumped away from relation_distance_, and the last one's distance.
  int jump_keyframes_ = 0;
  double jump_distance_ = 0;
  // RF off: the one global floor, fixed in the map frame once calibrated.
  bool has_global_ = false;
  FloorPlane global_;
};

}  // namespace valerant
