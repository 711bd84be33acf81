#include "valerant/explore/local_branch_pipeline.h"

#include <algorithm>
#include <optional>

#include "valerant/common/error.h"
#include "valerant/explore/branch_run.h"
#include "valerant/explore/branch_stages.h"
#include "valerant/slam/slam_factory.h"

namespace valerant {

LocalBranchPipeline::LocalBranchPipeline(const CameraIntrinsics& intrinsics, const Config& config)
    : config_(config),
      truth_(std::make_shared<RolloutTruth>()),
      slam_(makeSlam(config.slam.backend, intrinsics, config, truth_)),
      floor_(config.floor, Eigen::Vector3d::UnitZ(), config.collision.min_confidence, config.world.seed),
      committed_(config.collision, intrinsics) {}

BranchResult LocalBranchPipeline::start(const Rollout& context) {
  resume_->clear();
  BranchResult out;
  out.rollout = context;
  const RolloutTruth::Hold held = truth_->hold(context);
  for (size_t i = 0; i < context.frames.size(); ++i) {
    TrackedStep step = trackStep(*slam_, SlamInput{context.frames[i], {context.id, static_cast<int>(i)}});
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
  resume_->clear();
  slam_->restore(s.slam);
  floor_ = s.floor;
  committed_ = s.committed;
}

std::future<BranchResult> LocalBranchPipeline::evaluate(Rollout rollout, bool rotation_only,
                                                       std::vector<size_t> keep_after) {
  RolloutTruth::Hold held = truth_->hold(rollout);
  std::optional<BranchRun> resumed = resume_->longestPrefixOf(rollout);
  BranchRun run = resumed ? std::move(*resumed) : BranchRun(slam_->branch(), floor_, committed_.points(), config_);
  return std::async(std::launch::async, [held = std::move(held), rollout = std::move(rollout), rotation_only,
                                         run = std::move(run), keep_after = std::move(keep_after),
                                         resume = resume_]() mutable {
    const RolloutTruth::Hold until_evaluated = std::move(held);
    for (size_t i = run.frames(); i < rollout.frames.size(); ++i) {
      run.track(rollout.frames[i], rollout.id);
      if (std::find(keep_after.begin(), keep_after.end(), i + 1) != keep_after.end()) resume->keep(rollout, run.fork());
    }
    return std::move(run).finish(std::move(rollout), rotation_only);
  });
}

void LocalBranchPipeline::commit(const BranchResult& chosen) {
  auto* branch = dynamic_cast<LocalBranch*>(chosen.handle.get());
  if (!branch || !branch->slam)
    throw InputError("rollout " + std::to_string(chosen.rollout.id), "is no branch of this pipeline (or committed twice)");
  resume_->clear();
  slam_ = std::move(branch->slam);
  floor_ = branch->floor;
  committed_.add(chosen.keyframes, chosen.keyframe_floors);
}

}  // namespace valerant
