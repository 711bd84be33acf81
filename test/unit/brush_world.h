#pragma once
// Hand-made brush worlds for collision, kinematics and reachability tests.
#include <Eigen/Core>

#include "valerant/world/quake3/collision_model.h"

namespace valerant::test {

// An axis-aligned solid box brush [lo, hi].
inline quake3::ConvexBrush boxBrush(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  quake3::ConvexBrush b;
  b.planes = {{1, 0, 0, hi.x()},  {-1, 0, 0, -lo.x()}, {0, 1, 0, hi.y()},
              {0, -1, 0, -lo.y()}, {0, 0, 1, hi.z()},  {0, 0, -1, -lo.z()}};
  b.bounds = Eigen::AlignedBox3f(lo, hi);
  b.contents = quake3::kContentsSolid;
  return b;
}

}  // namespace valerant::test
