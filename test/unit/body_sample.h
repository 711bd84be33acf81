#pragma once
// A sample of eq. 6's body for the BodyPointIndex and BodyReach tests: the camera at c,
// the floor normal n (normalised here), the floor kappa below the camera along it.
#include "valerant/geometry/floor_plane.h"

namespace valerant::test {

inline FloorPlane sampleAt(const Eigen::Vector3d& c, const Eigen::Vector3d& n, double kappa) {
  FloorPlane s;
  s.n = n.normalized();
  s.c = c;
  s.q = c - kappa * s.n;
  return s;
}

}  // namespace valerant::test
