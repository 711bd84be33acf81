#pragma once
// The learned world backend (world.backend: learned; docs/world_model.md, "Backend"):
// WorldModelNet run autoregressively behind the WorldModel interface. The committed
// state is the net's last K frames at its own size (and, with the anchor warps, the
// anchor frame, coordinate map and, for pose_anchor, the anchor's depth and poses), so a checkpoint is a copy of a few small
// images. A rollout runs the net one frame per MotionStep from the committed context,
// sliding the K-frame window; the frames it returns are resized to world.width x
// world.height and intrinsics() is the world camera's, so SLAM and the rest of the
// graph see the same camera as with the engine. Deterministic: the same context and
// actions give the same bytes.
//
// Two starts:
//  - a screenshot (fromScreenshot): the image, resized to the net's size, repeated K
//    times as the context. No ground truth: every Rollout::truth is empty.
//  - an engine spawn (fromSpawn): a Quake3World "shadow" built from the same config
//    starts the context (its spawn view resized to the net's size, repeated K times)
//    and runs every rollout's actions too, giving Rollout::truth (poses, depth,
//    in-solid) for the ground-truth metrics. The frames are always the net's, never the
//    shadow's; commit / checkpoint / restore keep the shadow in step.
#include <deque>
#include <map>
#include <memory>
#include <optional>

#include "valerant/config/config.h"
#include "valerant/world/learned/world_model_net.h"
#include "valerant/world/quake3/quake3_world.h"
#include "valerant/world/world_model.h"

namespace valerant {

// The net of world.learned (model path relative to the package folder, as slam's depth
// prior), with the depth prior of world.learned.depth_prior_model for pose_anchor.
// Throws InputError naming the file when it cannot be loaded.
WorldModelNet loadWorldModelNet(const Config& config);

// An image file (PNG, JPEG, ... of any size) as CV_8UC3 RGB. Throws InputError naming
// `path` when it is missing, unreadable or empty.
cv::Mat readScreenshot(const std::string& path);

class LearnedWorld : public WorldModel {
 public:
  // From a screenshot: `rgb` CV_8UC3 RGB of any size (readScreenshot).
  static std::unique_ptr<LearnedWorld> fromScreenshot(WorldModelNet net, const cv::Mat& rgb, const Config& config);
  // From the engine spawn config.world.spawn of `map`, with the engine as truth shadow.
  static std::unique_ptr<LearnedWorld> fromSpawn(WorldModelNet net, std::shared_ptr<const quake3::Quake3Map> map,
                                                 const Config& config);

  CameraIntrinsics intrinsics() const override { return intrinsics_; }
  Rollout context() const override;
  CheckpointId checkpoint() override;
  void restore(CheckpointId id) override;
  void dropCheckpoint(CheckpointId id) override;
  Rollout rollout(const ActionSequence& actions) override;
  void commit(const Rollout& rollout) override;

  // The engine shadow of a spawn start (ground truth only); null for a screenshot start.
  const quake3::Quake3World* shadow() const { return shadow_ ? &*shadow_ : nullptr; }
  const WorldModelNet& net() const { return net_; }

 private:
  struct State {
    std::deque<cv::Mat> net_frames;  // the net's context: K frames at its size, oldest first
    AnchorState anchor;              // the anchor warps' state (anchor_warp.h)
    // The committed frames as shown (world size), up to K, with their truth (engine
    // start only): what context() returns; the start is one frame, not K copies.
    std::deque<cv::Mat> shown;
    std::deque<FrameTruth> shown_truth;
  };
  struct Saved {
    State state;
    CheckpointId shadow = 0;  // the shadow's checkpoint of the same state (engine start)
  };
  // The state a rollout made from the current state ends in, kept until the next commit
  // or restore, with the shadow's rollout of the same actions.
  struct Pending {
    State end;
    RolloutId shadow = 0;
  };

  LearnedWorld(WorldModelNet net, const cv::Mat& start_rgb, std::optional<FrameTruth> start_truth,
               std::unique_ptr<quake3::Quake3World> shadow, const Config& config);
  cv::Mat shownFrame(const cv::Mat& net_frame) const;  // resized to the world camera
  // Appends one frame to `state`, dropping the oldest beyond K.
  void push(State& state, const cv::Mat& net_frame, const cv::Mat& shown, const FrameTruth* truth) const;

  WorldModelNet net_;
  Config config_;
  CameraIntrinsics intrinsics_;
  std::unique_ptr<quake3::Quake3World> shadow_;
  State state_;
  std::map<CheckpointId, Saved> checkpoints_;
  CheckpointId next_checkpoint_ = 1;
  std::map<RolloutId, Pending> pending_;
  RolloutId next_rollout_ = 1;
};

}  // namespace valerant
