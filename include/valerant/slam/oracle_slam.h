#pragma once
// The upper bound for every ablation: a "SLAM" that reads the engine's ground-truth
// poses and depth (converted to metres, so the map frame is the BSP frame in metres)
// and reports a constant confidence above the paper's 4.0 cut. It reads them from the
// ground-truth source it is built with, by each input's stamp; a frame the source does
// not know is an InputError.
#include <memory>

#include "valerant/config/config.h"
#include "valerant/slam/ground_truth_source.h"
#include "valerant/slam/slam.h"

namespace valerant {

class OracleSlam : public Slam {
 public:
  // Throws InputError without a source.
  OracleSlam(const CameraIntrinsics& intrinsics, const SlamConfig& config,
             std::shared_ptr<const GroundTruthSource> truth);
  TrackedFrame track(const SlamInput& input) override;
  std::unique_ptr<Slam> branch() const override;
  std::shared_ptr<const SlamState> snapshot() const override;
  void restore(const std::shared_ptr<const SlamState>& state) override;
  std::vector<KeyframeCloud> keyframeClouds(int first = 0) const override;
  int keyframeCount() const override { return static_cast<int>(state_.keyframes.size()); }
  std::vector<Eigen::Isometry3d> trajectory() const override { return state_.trajectory; }
  CameraIntrinsics intrinsics() const override { return intrinsics_; }

 private:
  struct State : SlamState {
    std::vector<std::shared_ptr<const KeyframeCloud>> keyframes;  // shared by branches
    std::vector<Eigen::Isometry3d> trajectory;
  };
  CameraIntrinsics intrinsics_;
  SlamConfig config_;
  std::shared_ptr<const GroundTruthSource> truth_;  // shared by branches
  State state_;
};

// Back-projects every `stride`-th pixel with finite depth into the map frame.
std::vector<CloudPoint> backProject(const cv::Mat& rgb, const cv::Mat& depth, const cv::Mat& confidence,
                                    const CameraIntrinsics& k, const Eigen::Isometry3d& camera_to_map,
                                    int stride);

}  // namespace valerant
