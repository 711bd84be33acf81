#include "valerant/slam/visual/rotation_model.h"

#include <Eigen/SVD>
#include <algorithm>
#include <opencv2/calib3d.hpp>

#include "valerant/slam/visual/pinhole.h"

namespace valerant::visual {
namespace {

Eigen::Matrix3d nearestRotation(const Eigen::Matrix3d& m) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d r = svd.matrixU() * svd.matrixV().transpose();
  if (r.determinant() < 0) {
    Eigen::Matrix3d u = svd.matrixU();
    u.col(2) *= -1;
    r = u * svd.matrixV().transpose();
  }
  return r;
}

}  // namespace

std::optional<RotationEstimate> estimateRotation(const std::vector<cv::Point2f>& a,
                                                 const std::vector<cv::Point2f>& b, const CameraIntrinsics& k,
                                                 double threshold_px, int min_inliers) {
  if (static_cast<int>(a.size()) < std::max(min_inliers, 4)) return std::nullopt;
  std::vector<uchar> mask;
  const cv::Mat h = cv::findHomography(a, b, cv::RANSAC, threshold_px, mask, 2000, 0.999);
  if (h.empty()) return std::nullopt;
  Eigen::Matrix3d he;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) he(r, c) = h.at<double>(r, c);
  const Eigen::Matrix3d kk = eigenCameraMatrix(k);
  Eigen::Matrix3d m = kk.inverse() * he * kk;
  if (m.determinant() < 0) m = -m;  // a homography is defined up to sign
  RotationEstimate est;
  est.b_from_a = nearestRotation(m);

  // A homography also fits a translating camera in front of one plane; the rotation
  // refit and its residual below expose that case.
  auto residuals = [&](const Eigen::Matrix3d& rot) {
    std::vector<double> res(a.size());
    for (size_t i = 0; i < a.size(); ++i) {
      const Eigen::Vector3d p = rot * bearing(k, a[i]);
      res[i] = (project(k, p) - Eigen::Vector2d(b[i].x, b[i].y)).norm();
    }
    return res;
  };
  for (int pass = 0; pass < 2; ++pass) {
    const std::vector<double> res = residuals(est.b_from_a);
    std::vector<int> inliers;
    for (size_t i = 0; i < a.size(); ++i)
      if (res[i] < threshold_px * 2) inliers.push_back(static_cast<int>(i));
    if (static_cast<int>(inliers.size()) < min_inliers) return std::nullopt;
    Eigen::Matrix3Xd src(3, inliers.size()), dst(3, inliers.size());
    for (size_t j = 0; j < inliers.size(); ++j) {
      src.col(j) = bearing(k, a[inliers[j]]);
      dst.col(j) = bearing(k, b[inliers[j]]);
    }
    est.b_from_a = Eigen::umeyama(src, dst, false).topLeftCorner<3, 3>();
    est.inliers = std::move(inliers);
  }
  std::vector<double> res = residuals(est.b_from_a);
  std::nth_element(res.begin(), res.begin() + res.size() / 2, res.end());
  est.median_parallax_px = res[res.size() / 2];
  return est;
}

}  // namespace valerant::visual
