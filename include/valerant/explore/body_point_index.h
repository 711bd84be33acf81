#pragma once
// The body points of eq. 6 indexed for the per-sample count
//   count_i = #{p : |(p - c_i) - ((p - c_i).n_i) n_i|^2 <= (rho kappa_i)^2}
// which, done by brute force, costs samples x points: with the depth prior and the
// committed steps' points a branch has ~10^5 body points and ~100 samples, counted at
// two radii per candidate (rho and the prefix clearance) from one index.
//
// The points are binned on a 2D grid in the plane across a reference normal n0 (the
// first usable sample's). A sample's axis is tilted from n0 by a few degrees at most,
// and every body point lies in the slab [u_min, u_max] along n0, so the part of its
// cylinder that can hold points projects into a bounded box of cells; only the points
// there get the exact test. The counts are exactly the brute-force counts (the box is
// a conservative bound with a margin for rounding); a sample tilted more than 60 deg
// from n0 is counted by brute force.
#include <Eigen/Core>
#include <vector>

#include "valerant/geometry/floor_plane.h"

namespace valerant {

class BodyPointIndex {
 public:
  // `points`: finite positions; `radius`: normalised (rho), sets the cell size from the
  // first sample with a positive camera height.
  BodyPointIndex(const std::vector<Eigen::Vector3d>& points, const std::vector<FloorPlane>& samples, double radius);

  // count_i for one sample (0 where its camera height is not positive), at any radius
  // (a radius larger than the constructor's only makes the searched box wider).
  int count(const FloorPlane& sample, double radius) const;

 private:
  struct Binned {
    long long ix, iy;
    Eigen::Vector3d position;
  };
  int bruteForce(const FloorPlane& sample, double radius2) const;

  std::vector<Binned> binned_;  // sorted by (ix, iy)
  Eigen::Vector3d n0_, e1_, e2_;
  double cell_ = 0, u_min_ = 0, u_max_ = 0;
  bool indexed_ = false;  // false: every sample is counted by brute force
};

}  // namespace valerant
