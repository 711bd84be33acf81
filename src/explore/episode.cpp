#include "valerant/explore/episode.h"

#include <chrono>
#include <future>

#include "valerant/explore/policy.h"

namespace valerant {
namespace {

double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Before any floor is seen the vertical is the first camera's up: -y of its optical frame.
Eigen::Vector3d cameraUp(const Eigen::Isometry3d& camera_to_map) { return -camera_to_map.linear().col(1); }

}  // namespace

Episode::Episode(WorldModel& world, std::unique_ptr<Slam> slam, const Config& config)
    : world_(world),
      slam_(std::move(slam)),
      config_(config),
      d_fwd_normalised_(config.world.d_fwd_units / config.world.eye_height_units),
      floor_(config.floor, Eigen::Vector3d::UnitZ(), config.collision.min_confidence, config.world.seed),
      map_(config.map, config.collision),
      rewinder_(config.dead_pocket) {
  const Rollout context = world_.context();
  bool first = true;
  for (size_t i = 0; i < context.frames.size(); ++i) {
    SlamInput in;
    in.rgb = context.frames[i];
    if (i < context.truth.size()) in.truth = &context.truth[i];
    const TrackedFrame f = slam_->track(in);
    if (first) {
      floor_ = FloorEstimator(config.floor, cameraUp(f.camera_to_map), config.collision.min_confidence,
                              config.world.seed);
      first = false;
    }
    if (f.keyframe && slam_->keyframeCount() > 0) {
      const KeyframeCloud kf = slam_->keyframeClouds(slam_->keyframeCount() - 1).front();
      map_.fuse(kf, floor_.update(kf.points, f.camera_to_map));
    }
    trajectory_.push_back(f.camera_to_map);
    if (i < context.truth.size()) truth_.push_back(context.truth[i]);
  }
  anchorGrid();
}

void Episode::anchorGrid() {
  // The grid is anchored at the start pose on the floor plane; until a reliable floor
  // exists the anchor is provisional and is redone once one is found.
  const Eigen::Isometry3d& start = trajectory_.front();
  const FloorPlane anchor = floor_.at(start);
  anchor_kappa_ = anchor.cameraHeight();
  anchored_on_reliable_floor_ = floor_.hasReliable();
  grid_.emplace(config_.policy, anchor, start.linear().col(2), d_fwd_normalised_);
  for (const auto& pose : trajectory_) grid_->markVisited(pose.translation());
  for (const auto& kf : map_.keyframes())
    for (const auto& p : kf->points)
      if (std::abs(p.h) < config_.collision.height_low) grid_->markObservedFloor(p.position.cast<double>());
}

bool Episode::finished() const {
  return committed_steps_ >= config_.policy.budget_steps ||
         steps_ >= config_.policy.step_cap_factor * config_.policy.budget_steps;
}

StepRecord Episode::step() {
  const auto step_start = std::chrono::steady_clock::now();
  StepRecord record;
  record.step = ++steps_;
  record.checkpoint = world_.checkpoint();
  saved_.emplace(record.checkpoint, Saved{slam_->snapshot(), floor_, *grid_, map_.marker(), trajectory_.size(),
                                          committed_steps_});

  BranchContext ctx;
  ctx.committed_slam = slam_.get();
  ctx.committed_floor = &floor_;
  ctx.grid = &*grid_;
  ctx.failed = &failed_;
  ctx.start_centre = trajectory_.back().translation();
  ctx.d_fwd_normalised = d_fwd_normalised_;

  // Rendering needs the world's single GL context, so rollouts are made one after the
  // other; each one's reconstruction starts in its own thread as soon as it exists.
  std::vector<std::future<BranchOutcome>> pending;
  for (const std::string& name : candidateNames()) {
    const ActionSequence seq = makeActionSequence(name, config_);
    const auto t = std::chrono::steady_clock::now();
    Rollout rollout = world_.rollout(seq);
    record.seconds.render += secondsSince(t);
    pending.push_back(std::async(std::launch::async, evaluateBranch, std::move(rollout), seq.rotationOnly(),
                                 std::cref(ctx), std::cref(config_)));
  }
  std::vector<BranchOutcome> outcomes;
  std::vector<BranchVerdict> verdicts;
  for (auto& f : pending) {
    outcomes.push_back(f.get());
    verdicts.push_back(outcomes.back().verdict);
    record.seconds += outcomes.back().seconds;
  }
  const auto policy_start = std::chrono::steady_clock::now();
  record.chosen = selectBranch(verdicts, config_.policy, (uint64_t{config_.world.seed} << 32) + record.step);
  record.seconds.policy += secondsSince(policy_start);
  for (size_t i = 0; i < outcomes.size(); ++i)
    record.candidates.push_back({verdicts[i], outcomes[i].centres, outcomes[i].rollout.truth});

  Cell start_cell{-1, -1};
  grid_->cellOf(ctx.start_centre, start_cell);
  std::set<Cell> cells;
  bool rotation_only = false;
  if (record.chosen >= 0) {
    BranchOutcome& chosen = outcomes[record.chosen];
    rotation_only = chosen.rotation_only;
    for (const auto& c : chosen.centres) {
      Cell cell;
      if (grid_->cellOf(c, cell)) cells.insert(cell);
    }
    const auto t = std::chrono::steady_clock::now();
    commit(chosen);
    record.seconds.fusion += secondsSince(t);
  }
  release(rewinder_.recordStep(record.checkpoint, start_cell, record.chosen >= 0, rotation_only, cells));
  if (const auto decision = rewinder_.check()) rewind(*decision, record);
  record.map_keyframes = map_.marker();
  record.wall_seconds = secondsSince(step_start);
  history_.push_back(record);
  return record;
}

void Episode::commit(BranchOutcome& outcome) {
  world_.commit(outcome.rollout);
  slam_ = std::move(outcome.slam);
  floor_ = outcome.floor;
  for (size_t i = 0; i < outcome.keyframes.size(); ++i) map_.fuse(outcome.keyframes[i], outcome.keyframe_floors[i]);
  trajectory_.insert(trajectory_.end(), outcome.poses.begin(), outcome.poses.end());
  truth_.insert(truth_.end(), outcome.rollout.truth.begin(), outcome.rollout.truth.end());
  ++committed_steps_;
  if (!anchored_on_reliable_floor_ && floor_.hasReliable()) {
    anchorGrid();
    return;
  }
  for (const auto& c : outcome.centres) grid_->markVisited(c);
  for (size_t i = map_.marker() - outcome.keyframes.size(); i < map_.marker(); ++i)
    for (const auto& p : map_.keyframes()[i]->points)
      if (std::abs(p.h) < config_.collision.height_low) grid_->markObservedFloor(p.position.cast<double>());
}

void Episode::rewind(const RewindDecision& decision, StepRecord& record) {
  world_.restore(decision.checkpoint);
  const Saved& s = saved_.at(decision.checkpoint);
  slam_->restore(s.slam);
  floor_ = s.floor;
  grid_ = s.grid;
  map_.truncate(s.map_marker);
  trajectory_.resize(s.trajectory_size);
  if (truth_.size() > s.trajectory_size) truth_.resize(s.trajectory_size);
  committed_steps_ = s.committed_steps;
  failed_.add(decision.failed_cells);
  record.rewind = true;
  record.rewind_to = decision.checkpoint;
  record.discarded_steps = decision.discarded_steps;
  release(rewinder_.apply(decision));
}

void Episode::release(const std::vector<uint64_t>& checkpoints) {
  for (uint64_t id : checkpoints) {
    world_.dropCheckpoint(id);
    saved_.erase(id);
  }
}

void Episode::runUntilDone(const std::function<void(const StepRecord&)>& on_step, const std::atomic<bool>* stop) {
  while (!finished() && !(stop && stop->load())) {
    const StepRecord r = step();
    if (on_step) on_step(r);
  }
}

}  // namespace valerant
