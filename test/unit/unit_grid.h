#pragma once
// The unit coverage grid of the hand-worked grid tests: the anchor floor z = 0 with the
// eye 1 above the origin, looking along +X. Unit eye heights, and with d_fwd = 8 eye
// heights over 8 cells per d_fwd, unit cells: cell (64 + i, 64 + j) covers x in
// [i-.5, i+.5), y in [j-.5, j+.5), u = +X, v = n x u = +Y.
#include "valerant/geometry/coverage_grid.h"

namespace valerant::test {

inline FloorPlane unitAnchor() {
  FloorPlane anchor;
  anchor.q = {0, 0, 0};
  anchor.n = {0, 0, 1};
  anchor.c = {0, 0, 1};
  return anchor;
}

inline CoverageGrid unitGrid(const PolicyConfig& config = PolicyConfig{}) {
  return CoverageGrid(config, unitAnchor(), Eigen::Vector3d::UnitX(), 8.0);
}

}  // namespace valerant::test
