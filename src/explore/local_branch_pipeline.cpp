#include "valerant/explore/local_branch_pipeline.h"

#include "valerant/common/error.h"
#include "valerant/explore/branch_check.h"
#include "valerant/explore/branch_evaluator.h"
#include "valerant/explore/branch_stages.h"

namespace valerant {

LocalBranchPipeline::LocalBranchPipeline(std::unique_ptr<Slam> slam, const Config& config)
    : config_(config),
      slam_(std::move(slam)),
      floor_(config.floor, Eigen::Vector3d::UnitZ(), config.collision.min_confidence, config.world.seed),
      committed_(config.collision) {}

BranchResult LocalBranchPipeline::start(const Rollout& context) {
  BranchResult out;
  out.rollout = context;
  for (size_t i = 0; i < context.frames.size(); ++i) {
    const FrameTruth* truth = i < context.truth.size() ? &context.truth[i] : nullptr;
    TrackedStep step = trackStep(*slam_, context.frames[i], truth);
    if (i == 0) floor_ = startFloorEstimator(config_, step.frame.camera_to_map);
    if (step.keyframe) {
      out.keyframe_floors.push_back(floorStep(floor_, step.frame, &*step.keyframe));
      out.keyframes.push_back(std::move(*step.keyframe));
    }
    out.poses.push_back(step.frame.camera_to_map);
  }
  out.floor_reliable = floor_.hasReliable();
  return out;
}

void LocalBranchPipeline::checkpoint(CheckpointId id) { saved_.save(id, Saved{slam_->snapshot(), floor_, committed_}); }

void LocalBranchPipeline::restore(CheckpointId id) {
  const Saved& s = saved_.at(id);
  slam_->restore(s.slam);
  floor_ = s.floor;
  committed_ = s.committed;
}

std::future<BranchResult> LocalBranchPipeline::evaluate(Rollout rollout, bool rotation_only) {
  return std::async(std::launch::async, evaluateBranch, std::move(rollout), rotation_only, slam_->branch(), floor_,
                    committed_.points(), std::cref(config_));
}

void LocalBranchPipeline::commit(const BranchResult& chosen) {
  auto* branch = dynamic_cast<LocalBranch*>(chosen.handle.get());
  if (!branch || !branch->slam)
    throw InputError("rollout " + std::to_string(chosen.rollout.id), "is no branch of this pipeline (or committed twice)");
  slam_ = std::move(branch->slam);
  floor_ = branch->floor;
  committed_.add(chosen.keyframes);
}

}  // namespace valerant
