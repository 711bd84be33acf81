#pragma once
// The world model as the explorer sees it: a frozen
// action-conditioned video generator with checkpoints. A rollout imagines frames from
// the committed state without changing it; commit() makes one rollout the new
// committed state. Backends: quake3 (engine), bag (recorded rollouts), learned (a
// learned next-frame predictor: world/learned/learned_world.h).
#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "valerant/common/camera.h"
#include "valerant/world/action_sequence.h"

namespace valerant {

using CheckpointId = uint64_t;
using RolloutId = uint64_t;

// Ground truth of one frame. Only evaluation reads it: SLAM and the exploration
// policy consume Rollout::frames alone.
struct FrameTruth {
  Eigen::Isometry3d camera_to_world;  // optical frame in the BSP frame (game units)
  cv::Mat depth_m;                    // CV_32F metres along the optical axis, NaN = sky
  // The pose penetrates the world: hull_in_solid || outside_world. Everything that
  // counts or avoids penetrations reads this flag; the two below tell the reasons apart.
  bool in_solid = false;
  double floor_z = 0;                 // feet height the eye follows (game units)
  bool hull_in_solid = false;         // the player hull overlaps solid brushes
  bool hull_in_clip_only = false;     // ... nodraw player-clip brushes only: invisible
  bool outside_world = false;         // the hull's centre is outside the playable world
                                      // (walked through an outer wall into the void)
};

struct Rollout {
  RolloutId id = 0;
  std::string candidate;
  std::vector<cv::Mat> frames;  // CV_8UC3 RGB, one per action step
  std::vector<FrameTruth> truth;  // same length as frames; empty without ground truth
};

class WorldModel {
 public:
  virtual ~WorldModel() = default;
  virtual CameraIntrinsics intrinsics() const = 0;
  // The last K committed frames (fewer at the very start), oldest first, with their
  // ground truth where the backend has it; candidate "context".
  virtual Rollout context() const = 0;
  // Saves the committed state; ids increase and are never reused.
  virtual CheckpointId checkpoint() = 0;
  // Returns to a saved state. Throws InputError for an unknown or dropped id.
  virtual void restore(CheckpointId id) = 0;
  virtual void dropCheckpoint(CheckpointId id) = 0;
  // Imagines the frames of `actions` from the committed state (state unchanged).
  virtual Rollout rollout(const ActionSequence& actions) = 0;
  // Makes `rollout` (made from the current committed state) the committed state.
  // Throws InputError when the rollout does not start from the current state.
  virtual void commit(const Rollout& rollout) = 0;
};

}  // namespace valerant
