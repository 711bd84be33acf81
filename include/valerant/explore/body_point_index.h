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
// cylinder that can hold points projects into a bounded box of cells (body_reach.h);
// only the points there get the exact test. The counts are exactly the brute-force
// counts (the box is a conservative bound with a margin for rounding); a sample tilted
// more than 60 deg from n0 is counted by brute force.
//
// Told the largest radius it will be asked for, the index keeps only the points inside
// some sample's box at that radius: the committed steps' points cover the map around the
// branch, most of them far from its path, and sorting them all for every candidate made
// the collision stage of 150-step visual runs as costly as the SLAM. The dropped points
// lie outside every box, so no count changes; where some sample would be counted by brute
// force, every point is kept.
#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <vector>

#include "valerant/explore/body_reach.h"
#include "valerant/geometry/floor_plane.h"

namespace valerant {

class BodyPointIndex {
 public:
  // `points`: finite positions; `radius`: normalised (rho), sets the cell size from the
  // first sample with a positive camera height; `max_radius` (>= radius, or 0: no
  // bound), the largest radius any count will use, lets the index drop the points no
  // sample's cylinder of that radius can reach: its counts are then exact for the
  // samples given here only.
  BodyPointIndex(const std::vector<Eigen::Vector3d>& points, const std::vector<FloorPlane>& samples, double radius,
                 double max_radius = 0);

  // count_i for one sample (0 where its camera height is not positive), at any radius up
  // to max_radius (a radius larger than the constructor's only makes the searched box
  // wider; one over max_radius is a std::invalid_argument).
  int count(const FloorPlane& sample, double radius) const;

  // Calls visit(k) for the index k (into the constructor's `points`) of every point
  // within `radius` of the sample's axis, in no particular order: the points count()
  // counts (none where the camera height is not positive).
  template <class Visit>
  void forEachWithin(const FloorPlane& sample, double radius, Visit&& visit) const;

 private:
  struct Binned {
    long long ix, iy;
    Eigen::Vector3d position;
    size_t index;  // into the constructor's points
  };
  // The cells [ix0, ix1] x [iy0, iy1] that can hold the sample's points, or false where
  // the sample is searched by brute force; radius2 = (radius kappa)^2.
  bool searchBox(const FloorPlane& sample, double radius, long long box[4], double* radius2) const;
  // Throws std::invalid_argument for a radius over max_radius_.
  void checkRadius(double radius) const;
  // Drops the binned points outside the bounding box of every sample's span at
  // max_radius_ (none where a sample with a floor has no span).
  void keepReachable(const std::vector<FloorPlane>& samples);
  // The first binned point at or after cell (ix, iy).
  std::vector<Binned>::const_iterator firstAt(long long ix, long long iy) const;

  std::vector<Binned> binned_;  // sorted by (ix, iy)
  std::optional<BodyReach> reach_;  // none: every sample is counted by brute force
  double cell_ = 0, u_min_ = 0, u_max_ = 0;
  double max_radius_ = 0;  // 0: every radius
};

template <class Visit>
void BodyPointIndex::forEachWithin(const FloorPlane& sample, double radius, Visit&& visit) const {
  checkRadius(radius);
  const double kappa = sample.cameraHeight();
  if (!(kappa > 0)) return;
  long long box[4];
  double radius2 = 0;
  if (!searchBox(sample, radius, box, &radius2)) {
    for (const Binned& b : binned_)
      if (sample.axisDistanceSquared(b.position) <= radius2) visit(b.index);
    return;
  }
  for (long long ix = box[0]; ix <= box[1]; ++ix)
    for (auto it = firstAt(ix, box[2]); it != binned_.end() && it->ix == ix && it->iy <= box[3]; ++it)
      if (sample.axisDistanceSquared(it->position) <= radius2) visit(it->index);
}

}  // namespace valerant
