#pragma once
// Frames and floors of a synthetic branch for BranchCheck tests: the map frame is the
// first camera's optical frame (y down), the camera walks along +z, and the floor is
// the plane y = floor_y, so the camera-to-floor distance kappa is floor_y.
#include "valerant/config/config.h"
#include "valerant/explore/committed_points.h"
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

// A vertical edge (a brush's corner) known from the previous step: 40 confident points at
// x = `x`, z = `z`, y = 0.05 .. 0.245 (normalised heights 0.51 .. 0.9 over the floor
// y = 0.5, all within eq. 6's band).
inline CommittedSteps edgeAt(float x, float z) {
  KeyframeCloud edge;
  for (int k = 0; k < 40; ++k) edge.points.push_back({Eigen::Vector3f(x, 0.05f + 0.005f * k, z), {}, 10.f});
  CommittedPoints committed(Config().collision);
  committed.add({edge}, {floorBelow(Eigen::Vector3d::Zero(), 0.5)});
  return committed.points();
}

}  // namespace valerant::test
