#include "valerant/explore/clean_prefix.h"

namespace valerant {

int cleanPrefixFrames(const std::vector<FloorPlane>& frames, int first_unsafe, int reference, double margin,
                      double min_advance) {
  const int count = static_cast<int>(frames.size());
  if (first_unsafe < 0) return count;
  if (reference < 0 || reference >= count || first_unsafe > count) return 0;
  const FloorPlane& r = frames[reference];
  const double kappa = r.cameraHeight();
  if (!r.known || !(kappa > 0)) return 0;
  auto across = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const Eigen::Vector3d v = a - b;
    return (v - v.dot(r.n) * r.n).norm();
  };
  for (int k = first_unsafe; k >= 1; --k) {
    const Eigen::Vector3d& end = frames[k - 1].c;
    if (across(end, r.c) >= margin * kappa && across(end, frames.front().c) >= min_advance * kappa) return k;
  }
  return 0;
}

}  // namespace valerant
