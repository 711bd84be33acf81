#include "valerant/slam/visual/triangulation.h"

#include <cmath>
#include <opencv2/calib3d.hpp>

#include "valerant/slam/visual/pinhole.h"

namespace valerant::visual {
namespace {

cv::Matx34d projection(const CameraIntrinsics& k, const Eigen::Isometry3d& camera_to_map) {
  const Eigen::Matrix<double, 3, 4> rt = camera_to_map.inverse().matrix().topRows<3>();
  const Eigen::Matrix<double, 3, 4> p = eigenCameraMatrix(k) * rt;
  cv::Matx34d out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) out(r, c) = p(r, c);
  return out;
}

}  // namespace

std::vector<std::optional<Triangulated>> triangulate(const Eigen::Isometry3d& a_to_map,
                                                     const Eigen::Isometry3d& b_to_map,
                                                     const std::vector<cv::Point2f>& px_a,
                                                     const std::vector<cv::Point2f>& px_b,
                                                     const CameraIntrinsics& k, const TriangulationLimits& limits) {
  std::vector<std::optional<Triangulated>> out(px_a.size());
  if (px_a.empty()) return out;
  cv::Mat homogeneous;  // 4xN, CV_64F
  cv::triangulatePoints(projection(k, a_to_map), projection(k, b_to_map), px_a, px_b, homogeneous);
  homogeneous.convertTo(homogeneous, CV_64F);
  const Eigen::Isometry3d map_to_a = a_to_map.inverse(), map_to_b = b_to_map.inverse();
  const double min_cos = std::cos(limits.min_parallax_deg * M_PI / 180.0);
  for (size_t i = 0; i < px_a.size(); ++i) {
    const double w = homogeneous.at<double>(3, static_cast<int>(i));
    if (std::abs(w) < 1e-12) continue;
    const Eigen::Vector3d p(homogeneous.at<double>(0, static_cast<int>(i)) / w,
                            homogeneous.at<double>(1, static_cast<int>(i)) / w,
                            homogeneous.at<double>(2, static_cast<int>(i)) / w);
    const Eigen::Vector3d in_a = map_to_a * p, in_b = map_to_b * p;
    if (in_a.z() <= 0 || in_b.z() <= 0) continue;
    const Eigen::Vector3d ray_a = p - a_to_map.translation(), ray_b = p - b_to_map.translation();
    const double cos_parallax = ray_a.dot(ray_b) / (ray_a.norm() * ray_b.norm());
    if (cos_parallax > min_cos) continue;
    const double err_a = (project(k, in_a) - Eigen::Vector2d(px_a[i].x, px_a[i].y)).norm();
    const double err_b = (project(k, in_b) - Eigen::Vector2d(px_b[i].x, px_b[i].y)).norm();
    if (err_a > limits.max_reprojection_px || err_b > limits.max_reprojection_px) continue;
    out[i] = Triangulated{p, std::acos(std::min(1.0, cos_parallax)) * 180.0 / M_PI};
  }
  return out;
}

}  // namespace valerant::visual
