#include "valerant/slam/oracle_slam.h"

#include <cmath>
#include <string>

#include "valerant/common/error.h"
#include "valerant/world/quake3/units.h"

namespace valerant {

std::vector<CloudPoint> backProject(const cv::Mat& rgb, const cv::Mat& depth, const cv::Mat& confidence,
                                    const CameraIntrinsics& k, const Eigen::Isometry3d& camera_to_map,
                                    int stride) {
  std::vector<CloudPoint> points;
  const Eigen::Isometry3f t = camera_to_map.cast<float>();
  for (int v = stride / 2; v < depth.rows; v += stride) {
    for (int u = stride / 2; u < depth.cols; u += stride) {
      const float d = depth.at<float>(v, u);
      if (!std::isfinite(d) || d <= 0) continue;
      CloudPoint p;
      const Eigen::Vector3f ray(static_cast<float>((u - k.cx) / k.fx), static_cast<float>((v - k.cy) / k.fy), 1.f);
      p.position = t * (d * ray);
      const cv::Vec3b c = rgb.at<cv::Vec3b>(v, u);
      p.rgb = {c[0], c[1], c[2]};
      p.confidence = confidence.at<float>(v, u);
      points.push_back(p);
    }
  }
  return points;
}

OracleSlam::OracleSlam(const CameraIntrinsics& intrinsics, const SlamConfig& config,
                       std::shared_ptr<const GroundTruthSource> truth)
    : intrinsics_(intrinsics), config_(config), truth_(std::move(truth)) {
  if (!truth_) throw InputError("oracle SLAM", "needs a ground-truth source");
}

TrackedFrame OracleSlam::track(const SlamInput& input) {
  const std::optional<TrueView> view = truth_->viewOf(input.stamp);
  if (!view)
    throw InputError("oracle SLAM", "has no ground truth for frame " + std::to_string(input.stamp.index) +
                                        " of rollout " + std::to_string(input.stamp.rollout) +
                                        " (the world backend gave none)");
  const TrueView& truth = *view;
  TrackedFrame f;
  f.state = TrackingState::kTracking;
  f.camera_to_map = truth.camera_to_world;
  f.camera_to_map.translation() /= quake3::kUnitsPerMetre;
  if (!f.camera_to_map.matrix().allFinite()) {
    // A NaN pose must never reach the map: report the frame as lost instead.
    f.state = TrackingState::kLost;
    f.camera_to_map = state_.trajectory.empty() ? Eigen::Isometry3d::Identity() : state_.trajectory.back();
    state_.trajectory.push_back(f.camera_to_map);
    return f;
  }
  f.rotation_only = !state_.trajectory.empty() &&
                    (f.camera_to_map.translation() - state_.trajectory.back().translation()).norm() < 1e-9;
  f.depth = truth.depth_m.clone();
  f.confidence = cv::Mat(f.depth.size(), CV_32F, cv::Scalar(0));
  f.confidence.setTo(config_.oracle_confidence, f.depth == f.depth);  // NaN != NaN
  f.keyframe = state_.trajectory.size() % config_.oracle_keyframe_every == 0;
  if (f.keyframe) {
    auto kf = std::make_shared<KeyframeCloud>();
    kf->keyframe = static_cast<int>(state_.keyframes.size());
    kf->frame = static_cast<int>(state_.trajectory.size());
    kf->camera_to_map = f.camera_to_map;
    kf->points = backProject(input.rgb, f.depth, f.confidence, intrinsics_, f.camera_to_map,
                             config_.cloud_stride_px);
    state_.keyframes.push_back(std::move(kf));
  }
  state_.trajectory.push_back(f.camera_to_map);
  return f;
}

std::unique_ptr<Slam> OracleSlam::branch() const { return std::make_unique<OracleSlam>(*this); }

std::shared_ptr<const SlamState> OracleSlam::snapshot() const { return std::make_shared<State>(state_); }

void OracleSlam::restore(const std::shared_ptr<const SlamState>& state) {
  const auto* s = dynamic_cast<const State*>(state.get());
  if (!s) throw InputError("SLAM snapshot", "was not made by the oracle backend");
  state_ = *s;
}

std::vector<KeyframeCloud> OracleSlam::keyframeClouds(int first) const {
  std::vector<KeyframeCloud> out;
  for (size_t i = std::max(first, 0); i < state_.keyframes.size(); ++i) out.push_back(*state_.keyframes[i]);
  return out;
}

}  // namespace valerant
