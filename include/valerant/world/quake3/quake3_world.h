#pragma once
// The default world model: a Quake III map rendered offscreen and moved like a video
// world model (see camera_kinematics.h). Rollouts are deterministic for a seed, so a
// committed rollout is reused instead of replayed, and a rollout whose actions begin
// with those of another made from the same state (a short translation is uw's first
// 32 frames, a longer turn continues jq) reuses that one's frames and renders only the
// rest. One instance renders from one
// thread at a time (it owns an OSMesa context); branches in parallel use one instance
// each over the same shared Quake3Map.
#include <deque>
#include <map>
#include <memory>

#include "valerant/config/config.h"
#include "valerant/world/quake3/camera_kinematics.h"
#include "valerant/world/quake3/osmesa_renderer.h"
#include "valerant/world/quake3/quake3_map.h"
#include "valerant/world/world_model.h"

namespace valerant::quake3 {

class Quake3World : public WorldModel {
 public:
  // Starts at spawn point `config.world.spawn` with the spawn view as the only context
  // frame (the "single screenshot"). Throws InputError for a spawn index out of range.
  Quake3World(std::shared_ptr<const Quake3Map> map, const Config& config);

  CameraIntrinsics intrinsics() const override { return renderer_.intrinsics(); }
  Rollout context() const override;
  CheckpointId checkpoint() override;
  void restore(CheckpointId id) override;
  void dropCheckpoint(CheckpointId id) override;
  Rollout rollout(const ActionSequence& actions) override;
  void commit(const Rollout& rollout) override;

  // Ground truth and engine access (evaluation and tools only).
  const Quake3Map& map() const { return *map_; }
  const CameraKinematics& kinematics() const { return kinematics_; }
  const CameraState& camera() const { return state_.camera; }
  const std::vector<SpawnPoint>& spawnPoints() const { return spawns_; }
  // Renders the committed camera (colour + ground truth), without degradations.
  std::pair<cv::Mat, FrameTruth> observe() { return renderClean(state_.camera); }
  const TextureStats& textureStats() const { return renderer_.textureStats(); }

 private:
  struct State {
    CameraState camera;
    std::deque<cv::Mat> context;
    std::deque<FrameTruth> context_truth;
    uint64_t frames_committed = 0;  // keys the degradation randomness
  };
  std::pair<cv::Mat, FrameTruth> renderClean(const CameraState& camera);
  // Clean render plus the configured degradations, keyed by the frame's index.
  std::pair<cv::Mat, FrameTruth> renderFrame(const CameraState& camera, uint64_t frame_key);

  std::shared_ptr<const Quake3Map> map_;
  Config config_;
  std::vector<SpawnPoint> spawns_;
  CameraKinematics kinematics_;
  OsMesaRenderer renderer_;
  State state_;
  std::map<CheckpointId, State> checkpoints_;
  CheckpointId next_checkpoint_ = 1;
  // Rollouts made from the current committed state, with the state each one ends in
  // and what its frames were made of.
  struct Pending {
    State end;
    ActionSequence actions;
    std::vector<CameraState> cameras;  // one per frame
    std::vector<cv::Mat> frames;       // shared with the rollout handed out
    std::vector<FrameTruth> truth;
  };
  std::map<RolloutId, Pending> pending_;
  RolloutId next_rollout_ = 1;
};

}  // namespace valerant::quake3
