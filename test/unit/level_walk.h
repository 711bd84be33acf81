#pragma once
// The collision tests' level walk (test_collision.cpp, test_step_support.cpp): a floor
// z = 0 with the camera 1 above it (kappa = 1, so a point's normalised height is its z),
// the body walking along +X.
#include <vector>

#include "valerant/geometry/floor_plane.h"

namespace valerant::test {

// The floor under a camera at (x, 0, 1).
inline FloorPlane floorUnder(double x) {
  FloorPlane f;
  f.q = {x, 0, 0};
  f.n = {0, 0, 1};
  f.c = {x, 0, 1};
  f.reliable = true;
  return f;
}

// Samples from x0 to x1 in n frames: sample i at x0 + (x1 - x0) (i + 1) / n.
inline std::vector<FloorPlane> track(double x0, double x1, int n) {
  std::vector<FloorPlane> samples;
  for (int i = 1; i <= n; ++i) samples.push_back(floorUnder(x0 + (x1 - x0) * i / n));
  return samples;
}

}  // namespace valerant::test
