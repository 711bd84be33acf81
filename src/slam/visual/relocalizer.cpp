#include "valerant/slam/visual/relocalizer.h"

#include <opencv2/features2d.hpp>

#include "valerant/slam/visual/pnp_tracker.h"

namespace valerant::visual {
namespace {

cv::Ptr<cv::ORB> describer(const RelocalizerParams& params) {
  // One level: keypoints are given, and the frames compared are close in scale.
  return cv::ORB::create(1, 1.2f, 1, params.patch_px, 0, 2, cv::ORB::HARRIS_SCORE, params.patch_px);
}

// Describes `pixels`; `kept` gets the index of the pixel behind each descriptor row.
cv::Mat describe(const cv::Mat& grey, const std::vector<cv::Point2f>& pixels, const RelocalizerParams& params,
                 std::vector<int>& kept) {
  std::vector<cv::KeyPoint> keypoints;
  for (size_t i = 0; i < pixels.size(); ++i)
    keypoints.emplace_back(pixels[i], static_cast<float>(params.patch_px), 0.f, 0.f, 0, static_cast<int>(i));
  cv::Mat descriptors;
  describer(params)->compute(grey, keypoints, descriptors);
  kept.clear();
  for (const cv::KeyPoint& kp : keypoints) kept.push_back(kp.class_id);
  return descriptors;
}

}  // namespace

PointDescriptors describePoints(const cv::Mat& grey, const std::vector<std::pair<int, cv::Point2f>>& points,
                                const RelocalizerParams& params) {
  std::vector<cv::Point2f> pixels;
  for (const auto& p : points) pixels.push_back(p.second);
  std::vector<int> kept;
  PointDescriptors out;
  out.descriptors = describe(grey, pixels, params, kept);
  for (int i : kept) out.points.push_back(points[i].first);
  return out;
}

std::optional<Relocalization> relocalize(const cv::Mat& grey, const std::vector<cv::Point2f>& corners,
                                         const std::vector<const PointDescriptors*>& keyframes, const SlamMap& map,
                                         const CameraIntrinsics& k, const RelocalizerParams& params,
                                         const PnpParams& pnp) {
  std::vector<int> kept;
  const cv::Mat query = describe(grey, corners, params, kept);
  cv::Mat train;
  std::vector<int> train_points;
  for (const PointDescriptors* kf : keyframes) {
    for (int r = 0; r < kf->descriptors.rows; ++r) {
      if (!map.points[kf->points[r]]) continue;
      train.push_back(kf->descriptors.row(r));
      train_points.push_back(kf->points[r]);
    }
  }
  if (query.empty() || train.rows < 2) return std::nullopt;
  std::vector<std::vector<cv::DMatch>> knn;
  cv::BFMatcher(cv::NORM_HAMMING).knnMatch(query, train, knn, 2);
  std::vector<cv::Point3f> object;
  std::vector<cv::Point2f> image;
  std::vector<std::pair<size_t, int>> candidates;
  for (const auto& m : knn) {
    if (m.size() < 2 || m[0].distance > params.max_distance || m[0].distance > params.ratio * m[1].distance)
      continue;
    const int id = train_points[m[0].trainIdx];
    const size_t corner = static_cast<size_t>(kept[m[0].queryIdx]);
    const Eigen::Vector3f p = map.points[id]->position.cast<float>();
    object.emplace_back(p.x(), p.y(), p.z());
    image.push_back(corners[corner]);
    candidates.emplace_back(corner, id);
  }
  PnpParams strict = pnp;
  strict.min_inliers = params.min_inliers;
  const auto pose = solvePnp(object, image, k, strict);
  if (!pose) return std::nullopt;
  Relocalization out;
  out.camera_to_map = pose->camera_to_map;
  for (int i : pose->inliers) out.matches.push_back(candidates[i]);
  return out;
}

}  // namespace valerant::visual
