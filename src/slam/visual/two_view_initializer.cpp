#include "valerant/slam/visual/two_view_initializer.h"

#include <algorithm>
#include <opencv2/calib3d.hpp>

#include "valerant/slam/visual/pinhole.h"
#include "valerant/slam/visual/triangulation.h"

namespace valerant::visual {

std::optional<TwoViewResult> initializeTwoView(const std::vector<cv::Point2f>& a,
                                               const std::vector<cv::Point2f>& b, const CameraIntrinsics& k,
                                               const TwoViewParams& params) {
  if (static_cast<int>(a.size()) < params.min_points) return std::nullopt;
  const cv::Matx33d kk = cameraMatrix(k);
  cv::Mat mask;
  const cv::Mat e = cv::findEssentialMat(a, b, kk, cv::USAC_ACCURATE, 0.999, params.ransac_threshold_px, mask);
  if (e.rows != 3 || e.cols != 3) return std::nullopt;  // several solutions stacked = degenerate
  cv::Mat r, t;
  // recoverPose keeps, of the four decompositions, the one with most points in front
  // of both cameras, and zeroes the mask of points behind either.
  if (cv::recoverPose(e, a, b, kk, r, t, mask) < params.min_points) return std::nullopt;

  Eigen::Isometry3d a_from_b_world = Eigen::Isometry3d::Identity();  // x_b = R x_a + t
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) a_from_b_world.linear()(i, j) = r.at<double>(i, j);
    a_from_b_world.translation()(i) = t.at<double>(i);
  }
  TwoViewResult out;
  out.b_to_a = a_from_b_world.inverse();

  std::vector<cv::Point2f> in_a, in_b;
  std::vector<int> index;
  for (int i = 0; i < mask.rows; ++i) {
    if (!mask.at<uchar>(i)) continue;
    in_a.push_back(a[i]);
    in_b.push_back(b[i]);
    index.push_back(i);
  }
  const TriangulationLimits limits{params.min_point_parallax_deg, params.max_reprojection_px};
  const auto points = triangulate(Eigen::Isometry3d::Identity(), out.b_to_a, in_a, in_b, k, limits);
  std::vector<double> parallax;
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points[i]) continue;
    out.indices.push_back(index[i]);
    out.points.push_back(points[i]->position);
    parallax.push_back(points[i]->parallax_deg);
  }
  if (static_cast<int>(out.points.size()) < params.min_points) return out;
  std::nth_element(parallax.begin(), parallax.begin() + parallax.size() / 2, parallax.end());
  out.median_parallax_deg = parallax[parallax.size() / 2];
  out.ready = out.median_parallax_deg >= params.min_median_parallax_deg;
  return out;
}

}  // namespace valerant::visual
