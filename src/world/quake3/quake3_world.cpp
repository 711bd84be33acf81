#include "valerant/world/quake3/quake3_world.h"

#include <tuple>

#include "valerant/common/error.h"
#include "valerant/world/degradation.h"
#include "valerant/world/quake3/units.h"

namespace valerant::quake3 {
namespace {

RenderOptions renderOptions(const WorldConfig& w) {
  RenderOptions o;
  o.near_plane = static_cast<float>(w.near_plane_units);
  o.far_plane = static_cast<float>(w.far_plane_units);
  return o;
}

const SpawnPoint& pickSpawn(const std::vector<SpawnPoint>& spawns, int index, const std::string& map) {
  if (spawns.empty()) throw InputError("map '" + map + "'", "has no player spawn points");
  if (index < 0 || static_cast<size_t>(index) >= spawns.size())
    throw InputError("spawn " + std::to_string(index),
                     "out of range: map '" + map + "' has " + std::to_string(spawns.size()) + " spawn points");
  return spawns[index];
}

}  // namespace

Quake3World::Quake3World(std::shared_ptr<const Quake3Map> map, const Config& config)
    : map_(std::move(map)),
      config_(config),
      spawns_(map_->bsp.spawnPoints()),
      kinematics_(*map_->collision, config.world.eye_height_units, config.world.max_drop_units),
      renderer_(map_->bsp, map_->geometry, *map_->textures,
                CameraIntrinsics::fromHorizontalFov(config.world.width, config.world.height,
                                                    config.world.fov_x_deg),
                renderOptions(config.world)) {
  state_.camera = kinematics_.spawn(pickSpawn(spawns_, config.world.spawn, map_->bsp.name));
  auto [rgb, truth] = renderFrame(state_.camera, 0);
  state_.context.push_back(rgb);
  state_.context_truth.push_back(truth);
  state_.frames_committed = 1;
}

std::pair<cv::Mat, FrameTruth> Quake3World::renderClean(const CameraState& camera) {
  FrameTruth truth;
  truth.camera_to_world = kinematics_.cameraToWorld(camera);
  const RenderedView view = renderer_.render(truth.camera_to_world.cast<float>());
  truth.depth_m = view.depth / kUnitsPerMetre;
  truth.hull_in_solid = kinematics_.hullInSolid(camera);
  // Clip-only implies an overlap: the second brush search runs only for frames in solid.
  truth.hull_in_clip_only = truth.hull_in_solid && kinematics_.hullInClipOnly(camera);
  truth.outside_world = kinematics_.outsideWorld(camera);
  truth.in_solid = truth.hull_in_solid || truth.outside_world;
  truth.floor_z = camera.floor_z;
  return {view.rgb, truth};
}

std::pair<cv::Mat, FrameTruth> Quake3World::renderFrame(const CameraState& camera, uint64_t frame_key) {
  auto frame = renderClean(camera);
  const DegradationConfig& d = config_.world.degradation;
  if (degradationEnabled(d))
    frame.first = degradeFrame(frame.first, d, (uint64_t{config_.world.seed} << 32) ^ frame_key);
  return frame;
}

Rollout Quake3World::context() const {
  Rollout r;
  r.candidate = "context";
  r.frames.assign(state_.context.begin(), state_.context.end());
  r.truth.assign(state_.context_truth.begin(), state_.context_truth.end());
  return r;
}

CheckpointId Quake3World::checkpoint() {
  const CheckpointId id = next_checkpoint_++;
  checkpoints_[id] = state_;
  return id;
}

void Quake3World::restore(CheckpointId id) {
  auto it = checkpoints_.find(id);
  if (it == checkpoints_.end())
    throw InputError("checkpoint " + std::to_string(id), "unknown or already dropped");
  state_ = it->second;
  pending_.clear();
}

void Quake3World::dropCheckpoint(CheckpointId id) { checkpoints_.erase(id); }

Rollout Quake3World::rollout(const ActionSequence& actions) {
  // The pending rollout sharing the most leading actions, whose frames are reused.
  const Pending* base = nullptr;
  size_t shared = 0;
  for (const auto& [id, p] : pending_)
    if (const size_t n = sharedFrames(actions, p.actions); n > shared) base = &p, shared = n;
  Rollout r;
  r.id = next_rollout_++;
  r.candidate = actions.name;
  Pending made{state_, actions, {}, {}, {}};
  State& end = made.end;
  for (size_t i = 0; i < actions.steps.size(); ++i) {
    cv::Mat rgb;
    FrameTruth truth;
    if (i < shared) {
      end.camera = base->cameras[i];
      rgb = base->frames[i];
      truth = base->truth[i];
    } else {
      end.camera = kinematics_.step(end.camera, actions.steps[i]);
      std::tie(rgb, truth) = renderFrame(end.camera, end.frames_committed);
    }
    ++end.frames_committed;
    end.context.push_back(rgb);
    end.context_truth.push_back(truth);
    while (end.context.size() > static_cast<size_t>(config_.rollout.context_frames)) {
      end.context.pop_front();
      end.context_truth.pop_front();
    }
    made.cameras.push_back(end.camera);
    made.frames.push_back(rgb);
    made.truth.push_back(truth);
  }
  r.frames = made.frames;
  r.truth = made.truth;
  pending_[r.id] = std::move(made);
  return r;
}

void Quake3World::commit(const Rollout& rollout) {
  auto it = pending_.find(rollout.id);
  if (it == pending_.end())
    throw InputError("rollout " + std::to_string(rollout.id),
                     "was not made from the current committed state (stale after a commit or restore)");
  // The engine is deterministic: the rollout's end state is exactly what a replay of
  // its actions would reach, so it is reused instead of rendered again.
  state_ = std::move(it->second.end);
  pending_.clear();
}

}  // namespace valerant::quake3
