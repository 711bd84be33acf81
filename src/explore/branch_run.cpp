#include "valerant/explore/branch_run.h"

#include <chrono>

#include "valerant/explore/branch_stages.h"

namespace valerant {

BranchRun::BranchRun(std::unique_ptr<Slam> slam, FloorEstimator floor, CommittedSteps committed, const Config& config)
    : BranchRun(std::move(slam), std::move(floor), BranchCheck(config, std::move(committed))) {}

BranchRun::BranchRun(std::unique_ptr<Slam> slam, FloorEstimator floor, BranchCheck check)
    : slam_(std::move(slam)), floor_(std::move(floor)), check_(std::move(check)) {}

void BranchRun::track(const cv::Mat& rgb, uint64_t rollout_id) {
  auto t = std::chrono::steady_clock::now();
  const int index = static_cast<int>(poses_.size());
  TrackedStep step = trackStep(*slam_, SlamInput{rgb, {rollout_id, index}});
  seconds_.slam += secondsSince(t);
  t = std::chrono::steady_clock::now();
  const KeyframeCloud* keyframe = step.keyframe ? &*step.keyframe : nullptr;
  const FloorPlane plane = floorStep(floor_, step.frame, keyframe);
  seconds_.floor += secondsSince(t);
  t = std::chrono::steady_clock::now();
  check_.add(step.frame, keyframe, plane);
  poses_.push_back(step.frame.camera_to_map);
  if (keyframe) {
    keyframes_.push_back(std::move(*step.keyframe));
    keyframe_frames_.push_back(index);
  }
  seconds_.collision += secondsSince(t);
}

BranchRun BranchRun::fork() const {
  BranchRun copy(slam_->branch(), floor_, check_);
  copy.poses_ = poses_;
  copy.keyframes_ = keyframes_;
  copy.keyframe_frames_ = keyframe_frames_;
  return copy;
}

BranchResult BranchRun::finish(Rollout rollout, bool rotation_only) && {
  const auto t = std::chrono::steady_clock::now();
  BranchResult out;
  out.rollout = std::move(rollout);
  out.poses = std::move(poses_);
  out.keyframes = std::move(keyframes_);
  // Keyframes made before the branch's first floor get it back-filled (BranchCheck).
  const std::vector<FloorPlane> floors = check_.floors();
  for (size_t i : keyframe_frames_) out.keyframe_floors.push_back(floors[i]);
  out.verdict = check_.finish(out.rollout.candidate, rotation_only);
  out.floor_reliable = floor_.hasReliable();
  out.handle = std::make_shared<LocalBranch>(std::move(slam_), std::move(floor_));
  out.seconds = seconds_;
  out.seconds.collision += secondsSince(t);
  return out;
}

}  // namespace valerant
