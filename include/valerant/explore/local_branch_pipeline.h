#pragma once
// The branch pipeline in this process (what valerant_explore runs): one SLAM and one
// floor estimator hold the committed state; each candidate is evaluated on copies of
// them in a thread of its own; committing adopts the winner's copies (both backends
// are deterministic, so that equals replaying the winner). The pipeline feeds the SLAM
// every frame, so it also holds each rollout's ground truth while its frames are
// tracked: that is where the oracle backend reads it (slam/rollout_truth.h). A
// candidate that begins with the frames of an earlier one of the same step continues
// from that one's kept run (resume_points.h).
#include <memory>

#include "valerant/config/config.h"
#include "valerant/explore/branch_pipeline.h"
#include "valerant/explore/checkpoint_store.h"
#include "valerant/explore/committed_points.h"
#include "valerant/explore/floor_estimator.h"
#include "valerant/explore/resume_points.h"
#include "valerant/slam/rollout_truth.h"
#include "valerant/slam/slam.h"

namespace valerant {

class LocalBranchPipeline : public BranchPipeline {
 public:
  // A fresh SLAM of backend config.slam.backend; start() feeds it the context.
  LocalBranchPipeline(const CameraIntrinsics& intrinsics, const Config& config);

  BranchResult start(const Rollout& context) override;
  void checkpoint(CheckpointId id) override;
  void restore(CheckpointId id) override;
  void drop(CheckpointId id) override { saved_.drop(id); }
  std::future<BranchResult> evaluate(Rollout rollout, bool rotation_only, std::vector<size_t> keep_after) override;
  void commit(const BranchResult& chosen) override;
  FloorPlane floorAt(const Eigen::Isometry3d& camera_to_map) override { return floor_.at(camera_to_map); }

 private:
  struct Saved {
    std::shared_ptr<const SlamState> slam;
    FloorEstimator floor;
    CommittedPoints committed;
  };
  Config config_;
  std::shared_ptr<RolloutTruth> truth_;  // read by the oracle backend
  std::unique_ptr<Slam> slam_;
  FloorEstimator floor_;
  CommittedPoints committed_;  // counted by every branch's BranchCheck
  CheckpointStore<Saved> saved_;
  // Runs of this step's rollouts kept for later candidates that begin like them.
  std::shared_ptr<ResumePoints> resume_ = std::make_shared<ResumePoints>();
};

}  // namespace valerant
