#pragma once
// Frames and floors of a synthetic branch for BranchCheck tests: the map frame is the
// first camera's optical frame (y down), the camera walks along +z, and the floor is
// the plane y = floor_y, so the camera-to-floor distance kappa is floor_y.
#include "valerant/geometry/floor_plane.h"
#include "valerant/slam/slam.h"

namespace valerant::test {

inline TrackedFrame trackedAtZ(double z) {
  TrackedFrame f;
  f.state = TrackingState::kTracking;
  f.camera_to_map.translation() = Eigen::Vector3d(0, 0, z);
  return f;
}

inline FloorPlane floorBelow(const Eigen::Vector3d& c, double floor_y) {
  FloorPlane p;
  p.c = c;
  p.n = {0, -1, 0};
  p.q = {c.x(), floor_y, c.z()};
  p.reliable = true;
  return p;
}

}  // namespace valerant::test
