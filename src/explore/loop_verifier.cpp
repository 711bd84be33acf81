#include "valerant/explore/loop_verifier.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/features2d.hpp>
#include <sstream>

namespace valerant {
namespace {

constexpr int kPnpIterations = 200;
constexpr double kPnpConfidence = 0.999;
constexpr int kMinScalePairs = 10;     // inliers with depth on both keyframes for a scale
constexpr uint64_t kRansacSeed = 25;   // PnP RANSAC draws from OpenCV's thread RNG: a fixed seed, the same answer

std::string describe(const char* what, double value, const char* limit, double bound) {
  std::ostringstream s;
  s << what << " " << value << " " << limit << " " << bound;
  return s.str();
}

}  // namespace

LoopVerification verifyLoop(const KeyframeFeatures& old_keyframe, const KeyframeFeatures& new_keyframe,
                            const Similarity3& predicted, double eye_height, bool estimate_scale, const CameraIntrinsics& k,
                            const LoopClosureConfig& config) {
  LoopVerification out;
  std::vector<cv::Point3f> object;
  std::vector<cv::Point2f> image;
  std::vector<int> new_index;
  if (!old_keyframe.descriptors.empty() && !new_keyframe.descriptors.empty()) {
    cv::BFMatcher matcher(cv::NORM_HAMMING);
    std::vector<std::vector<cv::DMatch>> knn;
    matcher.knnMatch(new_keyframe.descriptors, old_keyframe.descriptors, knn, 2);
    for (const auto& m : knn) {
      if (m.empty() || m[0].distance > config.max_distance) continue;
      if (m.size() > 1 && !(m[0].distance < config.ratio * m[1].distance)) continue;
      const Eigen::Vector3f& p = old_keyframe.points[m[0].trainIdx];
      if (!std::isfinite(p.z())) continue;
      object.emplace_back(p.x(), p.y(), p.z());
      image.push_back(new_keyframe.pixels[m[0].queryIdx]);
      new_index.push_back(m[0].queryIdx);
    }
  }
  out.matches = static_cast<int>(object.size());
  if (out.matches < config.min_matches) {
    out.reason = "few_matches";
    out.detail = describe("matches", out.matches, "below min_matches", config.min_matches);
    return out;
  }

  const cv::Matx33d camera(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  cv::theRNG().state = kRansacSeed;
  const bool posed = cv::solvePnPRansac(object, image, camera, cv::noArray(), rvec, tvec, false, kPnpIterations,
                                        static_cast<float>(config.pnp_threshold_px), kPnpConfidence, inliers,
                                        cv::SOLVEPNP_EPNP);
  out.inliers = posed ? static_cast<int>(inliers.size()) : 0;
  if (out.inliers < config.min_inliers) {
    out.reason = "few_inliers";
    out.detail = describe("PnP inliers", out.inliers, "below min_inliers", config.min_inliers);
    return out;
  }
  cv::Mat rotation_cv;
  cv::Rodrigues(rvec, rotation_cv);
  Eigen::Matrix3d old_to_new;
  Eigen::Vector3d t;
  cv::cv2eigen(rotation_cv, old_to_new);
  cv::cv2eigen(tvec, t);

  double scale = 1;
  if (estimate_scale) {
    std::vector<double> ratios;
    for (int i : inliers) {
      const Eigen::Vector3f& own = new_keyframe.points[new_index[i]];
      const cv::Point3f& o = object[i];
      const double z = (old_to_new * Eigen::Vector3d(o.x, o.y, o.z) + t).z();
      if (std::isfinite(own.z()) && own.z() > 0 && z > 0) ratios.push_back(z / own.z());
    }
    if (static_cast<int>(ratios.size()) < kMinScalePairs) {
      out.reason = "no_scale";
      out.detail = describe("inliers with depth on the new keyframe", ratios.size(), "below", kMinScalePairs);
      return out;
    }
    std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
    scale = ratios[ratios.size() / 2];
  }
  // x_old = R^T (s x_new - t): the new camera (its own units) in the old camera's frame.
  const Eigen::Matrix3d new_to_old = old_to_new.transpose();
  out.relative = Similarity3{scale, Eigen::Quaterniond(new_to_old).normalized(), -(new_to_old * t)};

  out.offset_eye_heights = (out.relative.translation - predicted.translation).norm() / eye_height;
  out.rotation_deg = predicted.rotation.angularDistance(out.relative.rotation) * 180 / M_PI;
  out.scale_ratio = out.relative.scale / predicted.scale;
  if (out.offset_eye_heights > config.max_offset_eye_heights) {
    out.reason = "offset";
    out.detail = describe("offset from the prediction", out.offset_eye_heights, "eye heights, above",
                          config.max_offset_eye_heights);
  } else if (out.rotation_deg > config.max_rotation_deg) {
    out.reason = "rotation";
    out.detail = describe("rotation from the prediction", out.rotation_deg, "deg, above", config.max_rotation_deg);
  } else if (std::max(out.scale_ratio, 1 / out.scale_ratio) > config.max_scale_ratio) {
    out.reason = "scale";
    out.detail = describe("scale change", out.scale_ratio, "beyond the factor", config.max_scale_ratio);
  } else {
    out.accepted = true;
  }
  return out;
}

}  // namespace valerant
