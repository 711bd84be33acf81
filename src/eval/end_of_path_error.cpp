#include "valerant/eval/end_of_path_error.h"

#include <cmath>
#include <string>

#include "valerant/common/error.h"

namespace valerant {
namespace {

double degrees(double radians) { return radians * 180.0 / M_PI; }

}  // namespace

double cameraYawDeg(const Eigen::Isometry3d& camera_to_world) {
  const Eigen::Vector3d forward = camera_to_world.linear().col(2);
  return degrees(std::atan2(forward.y(), forward.x()));
}

double headingDeg(const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  const Eigen::Vector3d d = to - from;
  return degrees(std::atan2(d.y(), d.x()));
}

double angleBetweenDeg(double a_deg, double b_deg) {
  const double d = std::fmod(std::abs(a_deg - b_deg), 360.0);
  return d > 180.0 ? 360.0 - d : d;
}

EndOfPathError endOfPathError(const std::vector<Eigen::Isometry3d>& estimate,
                              const std::vector<Eigen::Isometry3d>& truth, bool translates) {
  if (estimate.empty() || estimate.size() != truth.size())
    throw InputError("camera paths", "need one estimated pose per true pose and at least one, got " +
                                         std::to_string(estimate.size()) + " and " + std::to_string(truth.size()));
  const Eigen::Isometry3d map_to_world = truth.front() * estimate.front().inverse();
  const Eigen::Isometry3d start = map_to_world * estimate.front(), end = map_to_world * estimate.back();
  EndOfPathError e;
  e.yaw_error_deg = angleBetweenDeg(cameraYawDeg(end), cameraYawDeg(truth.back()));
  if (translates) {
    const Eigen::Vector3d moved = end.translation() - start.translation();
    e.heading_error_deg = moved.head<2>().norm() == 0
                              ? 180.0
                              : angleBetweenDeg(headingDeg(start.translation(), end.translation()),
                                                headingDeg(truth.front().translation(), truth.back().translation()));
  }
  return e;
}

}  // namespace valerant
