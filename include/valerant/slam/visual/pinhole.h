#pragma once
// Pinhole helpers shared by the visual SLAM parts: OpenCV camera matrix, projection,
// bearings, OpenCV rvec/tvec -> pose, and intrinsics of a downsampled image.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "valerant/common/camera.h"

namespace valerant::visual {

inline cv::Matx33d cameraMatrix(const CameraIntrinsics& k) {
  return cv::Matx33d(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
}

inline Eigen::Matrix3d eigenCameraMatrix(const CameraIntrinsics& k) {
  Eigen::Matrix3d m;
  m << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1;
  return m;
}

inline Eigen::Vector2d project(const CameraIntrinsics& k, const Eigen::Vector3d& p_camera) {
  return {k.fx * p_camera.x() / p_camera.z() + k.cx, k.fy * p_camera.y() / p_camera.z() + k.cy};
}

// Unit ray through a pixel, in the optical frame.
inline Eigen::Vector3d bearing(const CameraIntrinsics& k, const cv::Point2f& px) {
  return Eigen::Vector3d((px.x - k.cx) / k.fx, (px.y - k.cy) / k.fy, 1.0).normalized();
}

// Intrinsics of the image shrunk by `factor` with pixel-area averaging (cv::INTER_AREA):
// pixel centres map as u' = (u + 0.5) / factor - 0.5.
inline CameraIntrinsics downsampled(const CameraIntrinsics& k, int factor) {
  CameraIntrinsics d = k;
  d.width = k.width / factor;
  d.height = k.height / factor;
  d.fx = k.fx / factor;
  d.fy = k.fy / factor;
  d.cx = (k.cx + 0.5) / factor - 0.5;
  d.cy = (k.cy + 0.5) / factor - 0.5;
  return d;
}

// OpenCV's (rvec, tvec) map world points into the camera: camera_to_map is the inverse.
inline Eigen::Isometry3d fromRvecTvec(const cv::Vec3d& rvec, const cv::Vec3d& tvec) {
  const Eigen::Vector3d r(rvec[0], rvec[1], rvec[2]);
  Eigen::Isometry3d map_to_camera = Eigen::Isometry3d::Identity();
  const double angle = r.norm();
  if (angle > 0) map_to_camera.linear() = Eigen::AngleAxisd(angle, r / angle).toRotationMatrix();
  map_to_camera.translation() = Eigen::Vector3d(tvec[0], tvec[1], tvec[2]);
  return map_to_camera.inverse();
}

}  // namespace valerant::visual
