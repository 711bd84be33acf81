#pragma once
// Reconstructs and judges one candidate rollout (paper section 3.2-3.3): its own SLAM
// branch tracks the frames, its own copy of the floor estimator follows each keyframe
// (RF), then the point-cloud and depth collision tests, the failed-region test and the
// coverage/progress terms fill a BranchVerdict. Pure with respect to the committed
// state, so the five candidates run in parallel threads.
#include <memory>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/explore/branch_verdict.h"
#include "valerant/explore/coverage_grid.h"
#include "valerant/explore/failed_region_memory.h"
#include "valerant/explore/floor_estimator.h"
#include "valerant/slam/slam.h"
#include "valerant/world/world_model.h"

namespace valerant {

struct StageSeconds {
  double render = 0, slam = 0, floor = 0, collision = 0, policy = 0, fusion = 0;
  StageSeconds& operator+=(const StageSeconds& o);
};

struct BranchOutcome {
  Rollout rollout;
  bool rotation_only = false;
  std::unique_ptr<Slam> slam;  // the branch's SLAM after tracking the rollout
  FloorEstimator floor;        // the branch's floor estimator after its keyframes
  std::vector<Eigen::Isometry3d> poses;             // per frame, map frame
  std::vector<KeyframeCloud> keyframes;             // new keyframes of this branch
  std::vector<FloorPlane> keyframe_floors;          // their floors
  std::vector<Eigen::Vector3d> centres;             // start centre, then one per frame
  BranchVerdict verdict;  // score/admissible are filled by selectBranch()
  StageSeconds seconds;
};

struct BranchContext {
  const Slam* committed_slam = nullptr;
  const FloorEstimator* committed_floor = nullptr;
  const CoverageGrid* grid = nullptr;
  const FailedRegionMemory* failed = nullptr;
  Eigen::Vector3d start_centre;  // committed camera centre
  double d_fwd_normalised = 0;   // d_fwd / eye height
};

BranchOutcome evaluateBranch(Rollout rollout, bool rotation_only, const BranchContext& context,
                             const Config& config);

}  // namespace valerant
