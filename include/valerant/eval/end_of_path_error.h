#pragma once
// Where a recovered camera path ends up against the true one, in the two angles an
// explorer acts on: the camera's yaw (rotation about the world's vertical) and the
// heading of the net horizontal translation. Both are free of the monocular scale.
// World frame: the BSP frame, z up; camera: optical frame, z forward.
#include <Eigen/Geometry>
#include <optional>
#include <vector>

namespace valerant {

// The optical axis's direction in the horizontal plane, degrees counter-clockwise from
// +x seen from above (atan2 of its x, y parts).
double cameraYawDeg(const Eigen::Isometry3d& camera_to_world);

// Direction of the horizontal displacement from `from` to `to`, degrees counter-clockwise
// from +x.
double headingDeg(const Eigen::Vector3d& from, const Eigen::Vector3d& to);

// |a - b| wrapped into [0, 180] degrees.
double angleBetweenDeg(double a_deg, double b_deg);

struct EndOfPathError {
  double yaw_error_deg = 0;
  std::optional<double> heading_error_deg;  // only for a path that translates
};

// `estimate`: a SLAM's poses (camera_to_map, any scale) of the frames whose true poses
// are `truth` (camera_to_world). The first frame's pose is known, so the estimate is
// carried into the world frame by it: aligned_i = truth_0 * estimate_0^-1 * estimate_i.
// The errors are those of the last frame: yaw against the true yaw, and when
// `translates`, the heading of aligned_last - aligned_0 against that of truth_last -
// truth_0; an estimate that did not move horizontally tells no heading and counts as
// 180 degrees off. Throws InputError for lists of different or zero length.
EndOfPathError endOfPathError(const std::vector<Eigen::Isometry3d>& estimate,
                              const std::vector<Eigen::Isometry3d>& truth, bool translates);

}  // namespace valerant
