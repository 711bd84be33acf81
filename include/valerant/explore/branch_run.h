#pragma once
// Reconstructs and judges one candidate rollout in this process (paper section
// 3.2-3.3), one frame at a time: its own SLAM branch tracks each frame, its own copy of
// the floor estimator follows each keyframe (RF), and BranchCheck collects the
// collision tests. Pure with respect to the committed state, so the candidates of a
// step run in parallel threads. The ROS graph runs the same stages in the branch_slam,
// floor_estimator and collision_checker nodes.
//
// A run can be forked after any frame and continued with other frames: both SLAM
// backends, the floor estimator and the tests are deterministic and causal (no frame's
// result depends on a later frame), so a rollout that begins with the same frames
// continues from the fork exactly as tracking those frames again would (resume_points.h).
#include <memory>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/explore/branch_check.h"
#include "valerant/explore/branch_pipeline.h"
#include "valerant/explore/committed_points.h"
#include "valerant/explore/floor_estimator.h"
#include "valerant/slam/slam.h"

namespace valerant {

// The branch's SLAM and floor estimator after the rollout: what committing it adopts.
struct LocalBranch : BranchHandle {
  LocalBranch(std::unique_ptr<Slam> s, FloorEstimator f) : slam(std::move(s)), floor(std::move(f)) {}
  std::unique_ptr<Slam> slam;
  FloorEstimator floor;
};

class BranchRun {
 public:
  // `slam` and `floor` are the branch's own copies of the committed state;
  // `committed` the latest committed steps' points (CommittedPoints).
  BranchRun(std::unique_ptr<Slam> slam, FloorEstimator floor, CommittedSteps committed, const Config& config);

  // Tracks the next frame (its index in the rollout is frames()).
  void track(const cv::Mat& rgb, uint64_t rollout_id);
  size_t frames() const { return poses_.size(); }
  // An independent copy of the run so far, on a branch of its SLAM; its stage seconds
  // start at zero (the work so far was counted once, here).
  BranchRun fork() const;
  // The result of the frames tracked, as the branch of `rollout` (whose frames they are).
  BranchResult finish(Rollout rollout, bool rotation_only) &&;

 private:
  BranchRun(std::unique_ptr<Slam> slam, FloorEstimator floor, BranchCheck check);

  std::unique_ptr<Slam> slam_;
  FloorEstimator floor_;
  BranchCheck check_;
  std::vector<Eigen::Isometry3d> poses_;
  std::vector<KeyframeCloud> keyframes_;
  std::vector<size_t> keyframe_frames_;
  StageSeconds seconds_;
};

}  // namespace valerant
