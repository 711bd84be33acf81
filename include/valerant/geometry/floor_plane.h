#pragma once
// A local floor plane and the paper's floor-normalised height (eq. 5):
//   h(p) = n.(p - q) / n.(c - q)
// with q on the plane, n its unit normal oriented toward the camera centre c. The
// floor has h = 0 and the camera h = 1, so a common translation or scale drift of the
// reconstruction cancels out.
#include <Eigen/Core>

namespace valerant {

struct FloorPlane {
  Eigen::Vector3d q = Eigen::Vector3d::Zero();
  Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d c = Eigen::Vector3d::UnitZ();
  bool reliable = false;  // fitted on this keyframe (else propagated)
  // False while the estimator has never accepted a floor: q and n are then a
  // placeholder, and no height or camera-to-floor distance may be read from them.
  bool known = true;
  int support = 0;        // RANSAC inliers of the fit

  // kappa: camera-to-floor distance in map units.
  double cameraHeight() const { return n.dot(c - q); }
  double normalisedHeight(const Eigen::Vector3d& p) const { return n.dot(p - q) / cameraHeight(); }
  // Squared distance of p from the body axis (the line through c along n), map units.
  double axisDistanceSquared(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d v = p - c;
    return (v - v.dot(n) * n).squaredNorm();
  }
};

}  // namespace valerant
