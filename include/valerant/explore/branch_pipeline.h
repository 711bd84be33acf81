#pragma once
// The per-branch half of an exploration step: SLAM, floor
// and collision for each candidate rollout, and the per-branch state carried from step
// to step (the committed SLAM and floor estimator) saved under the world model's
// synchronised checkpoint ids. Episode drives one. LocalBranchPipeline runs it in this
// process; ros::RosBranchPipeline proxies it to the branch_slam, floor_estimator and
// collision_checker nodes. Both run the same stage code (branch_stages.h,
// branch_check.h) on bit-identical data, so an episode decides the same either way.
#include <Eigen/Geometry>
#include <future>
#include <memory>
#include <vector>

#include "valerant/explore/branch_verdict.h"
#include "valerant/explore/stage_seconds.h"
#include "valerant/geometry/floor_plane.h"
#include "valerant/slam/slam.h"
#include "valerant/world/world_model.h"

namespace valerant {

// Whatever a pipeline keeps of one branch in order to commit it later (in this
// process: its SLAM and floor estimator; nothing when the branch lives elsewhere).
class BranchHandle {
 public:
  virtual ~BranchHandle() = default;
};

// One candidate rollout reconstructed and judged, or the committed context tracked.
struct BranchResult {
  Rollout rollout;                          // id, candidate, ground truth (frames may be absent)
  std::vector<Eigen::Isometry3d> poses;     // one per frame, map frame
  std::vector<KeyframeCloud> keyframes;     // keyframes made on this branch
  std::vector<FloorPlane> keyframe_floors;  // their floors
  bool floor_reliable = false;              // the branch's floor estimator found a reliable floor
  BranchVerdict verdict;                    // collision tests and SLAM loss; Episode adds the rest
  StageSeconds seconds;
  std::shared_ptr<BranchHandle> handle;
};

class BranchPipeline {
 public:
  virtual ~BranchPipeline() = default;
  // Tracks the world's committed context into a fresh committed state (episode start).
  virtual BranchResult start(const Rollout& context) = 0;
  virtual void checkpoint(CheckpointId id) = 0;
  // Throws InputError for an unknown or dropped id.
  virtual void restore(CheckpointId id) = 0;
  virtual void drop(CheckpointId id) = 0;
  // Reconstructs and judges `rollout` (made from the committed state) on a branch of
  // its own; the five candidates of a step run concurrently. `keep_after`: frame counts
  // whose states a later candidate of this step may begin with (a shorter or longer
  // version of this one); a pipeline may keep them and resume from there, with the
  // result tracking the frames again would give, or ignore them.
  virtual std::future<BranchResult> evaluate(Rollout rollout, bool rotation_only,
                                             std::vector<size_t> keep_after) = 0;
  // Makes the branch of `chosen` (a result of this step's evaluate) the committed state.
  virtual void commit(const BranchResult& chosen) = 0;
  // The committed floor estimator's floor at a pose (anchors the coverage grid).
  virtual FloorPlane floorAt(const Eigen::Isometry3d& camera_to_map) = 0;
};

}  // namespace valerant
