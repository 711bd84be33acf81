#include "valerant/slam/visual/pnp_tracker.h"

#include <opencv2/calib3d.hpp>

#include "valerant/slam/visual/pinhole.h"

namespace valerant::visual {

std::optional<PnpResult> solvePnp(const std::vector<cv::Point3f>& points, const std::vector<cv::Point2f>& pixels,
                                  const CameraIntrinsics& k, const PnpParams& params) {
  if (static_cast<int>(points.size()) < params.min_inliers) return std::nullopt;
  cv::Vec3d rvec, tvec;
  std::vector<int> inliers;
  const cv::Matx33d kk = cameraMatrix(k);
  // No extrinsic guess: OpenCV then refines its final pose from the guess rather than
  // from the RANSAC model, which can fall into a wrong minimum.
  const bool ok = cv::solvePnPRansac(points, pixels, kk, cv::noArray(), rvec, tvec, false, params.iterations,
                                     static_cast<float>(params.threshold_px), params.confidence, inliers,
                                     cv::SOLVEPNP_EPNP);
  if (!ok || static_cast<int>(inliers.size()) < params.min_inliers) return std::nullopt;
  std::vector<cv::Point3f> in_points;
  std::vector<cv::Point2f> in_pixels;
  for (int i : inliers) {
    in_points.push_back(points[i]);
    in_pixels.push_back(pixels[i]);
  }
  cv::solvePnPRefineLM(in_points, in_pixels, kk, cv::noArray(), rvec, tvec);
  PnpResult out;
  out.camera_to_map = fromRvecTvec(rvec, tvec);
  if (!out.camera_to_map.matrix().allFinite()) return std::nullopt;
  // Re-collect inliers against the refined pose: RANSAC's set came from a minimal sample.
  const Eigen::Isometry3d map_to_camera = out.camera_to_map.inverse();
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d p = map_to_camera * Eigen::Vector3d(points[i].x, points[i].y, points[i].z);
    if (p.z() <= 0) continue;
    if ((project(k, p) - Eigen::Vector2d(pixels[i].x, pixels[i].y)).norm() < params.threshold_px)
      out.inliers.push_back(static_cast<int>(i));
  }
  if (static_cast<int>(out.inliers.size()) < params.min_inliers) return std::nullopt;
  return out;
}

}  // namespace valerant::visual
