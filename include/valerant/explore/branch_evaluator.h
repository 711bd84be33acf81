#pragma once
// Reconstructs and judges one candidate rollout in this process (paper section
// 3.2-3.3): its own SLAM branch tracks the frames, its own copy of the floor estimator
// follows each keyframe (RF), and BranchCheck runs the collision tests. Pure with
// respect to the committed state, so the five candidates run in parallel threads. The
// ROS graph runs the same stages in the branch_slam, floor_estimator and
// collision_checker nodes.
#include <memory>

#include "valerant/config/config.h"
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

// `slam` and `floor` are the branch's own copies of the committed state;
// `committed` the latest committed steps' points (CommittedPoints).
BranchResult evaluateBranch(Rollout rollout, bool rotation_only, std::unique_ptr<Slam> slam, FloorEstimator floor,
                            CommittedSteps committed, const Config& config);

}  // namespace valerant
