#pragma once
// Pinhole camera intrinsics and the optical-frame convention used everywhere:
// x right, y down, z forward (REP-103 optical frame).
#include <Eigen/Geometry>
#include <cmath>

namespace valerant {

struct CameraIntrinsics {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;

  // Square pixels, principal point at the image centre, horizontal field of view.
  static CameraIntrinsics fromHorizontalFov(int width, int height, double fov_x_deg) {
    CameraIntrinsics k;
    k.width = width;
    k.height = height;
    k.fx = k.fy = 0.5 * width / std::tan(0.5 * fov_x_deg * M_PI / 180.0);
    k.cx = 0.5 * width;
    k.cy = 0.5 * height;
    return k;
  }
  double verticalFovDeg() const { return 2.0 * std::atan(0.5 * height / fy) * 180.0 / M_PI; }
};

}  // namespace valerant
