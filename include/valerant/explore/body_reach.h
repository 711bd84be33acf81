#pragma once
// Where the body cylinders of eq. 6 can reach: the bound BodyPointIndex searches its
// cells by, and that BranchCheck filters the committed steps' points by before it copies
// them (a branch's samples reach a strip of the map; the committed steps' points cover
// the map around it, and copying them all for every candidate cost a fifth of a 150-step
// visual run's CPU, much of it in page faults; docs/long_episodes.md).
//
// Sample i counts p where |(p - c_i) - ((p - c_i).n_i) n_i| <= r_i (r_i = radius kappa_i).
// The axes are tilted a few degrees at most from a reference normal n0 (the first sample
// with a floor's), and the points lie in a slab u_min <= p.n0 <= u_max. Such a p lies
// on p = c_i + t n_i + e, |e| <= r_i, with t between (u_min - c_i.n0 - r_i) / (n_i.n0) and
// (u_max - c_i.n0 + r_i) / (n_i.n0); so across n0, along e1 and e2 (an orthonormal pair
// across n0), it lies within r_i of the projection of that stretch of the axis: a box.
// A sample tilted more than 60 degrees from n0 has no bounded box.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "valerant/geometry/floor_plane.h"

namespace valerant {

// The first sample whose camera height is positive and finite and whose c and n are
// finite (nullptr if none): the one whose normal is n0.
const FloorPlane* referenceSample(const std::vector<FloorPlane>& samples);

// A box in the plane across n0: a along e1, b along e2.
struct PlaneBox {
  double a_lo = 0, a_hi = 0, b_lo = 0, b_hi = 0;
  bool contains(double a, double b) const { return a >= a_lo && a <= a_hi && b >= b_lo && b <= b_hi; }
  // The smallest box holding both.
  PlaneBox joined(const PlaneBox& other) const;
};

class BodyReach {
 public:
  // n0 = the reference's normal, normalised.
  explicit BodyReach(const FloorPlane& reference);

  double along(const Eigen::Vector3d& p) const { return p.dot(n0_); }  // u
  double across1(const Eigen::Vector3d& p) const { return p.dot(e1_); }  // a
  double across2(const Eigen::Vector3d& p) const { return p.dot(e2_); }  // b

  // The box holding every point of the slab within `radius` (normalised) of the sample's
  // axis, with a margin for rounding; nullopt where the sample is tilted more than 60
  // degrees from n0, its normal is not a unit vector, or a coordinate is not finite.
  std::optional<PlaneBox> span(const FloorPlane& sample, double radius, double u_min, double u_max) const;
  // The box holding every sample's span (samples whose camera height is not positive
  // reach nothing); nullopt where some other sample has no span, or none reaches anything.
  std::optional<PlaneBox> spanOfAll(const std::vector<FloorPlane>& samples, double radius, double u_min,
                                    double u_max) const;

 private:
  Eigen::Vector3d n0_, e1_, e2_;
};

// A box across n0 with the frame that measures it: the points some body can reach.
struct ReachableBox {
  BodyReach frame;
  PlaneBox box;
  bool contains(const Eigen::Vector3d& p) const { return box.contains(frame.across1(p), frame.across2(p)); }
};

}  // namespace valerant
