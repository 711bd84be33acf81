#pragma once
// The SLAM interface every branch uses: RGB frames in, camera
// poses, per-frame raw depth with confidence, and keyframe point clouds out, all in the
// frame of the committed map. Branching is cheap: branch() starts an independent SLAM
// from the current state, sharing the immutable keyframes and points already made;
// snapshot()/restore() save and return to a state for rewinds.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "valerant/common/camera.h"

namespace valerant {

enum class TrackingState { kInitializing, kTracking, kLost };

const char* toString(TrackingState state);

// One reconstructed point: position in the SLAM map frame (arbitrary scale), colour,
// and a confidence on the scale of the paper's threshold 4.0 (see the backend header).
struct CloudPoint {
  Eigen::Vector3f position;
  std::array<uint8_t, 3> rgb{};
  float confidence = 0;
};

struct KeyframeCloud {
  int keyframe = 0;                      // index in the SLAM's keyframe sequence
  int frame = 0;                         // index of the tracked frame it came from
  Eigen::Isometry3d camera_to_map;       // optical frame
  std::vector<CloudPoint> points;
};

struct TrackedFrame {
  TrackingState state = TrackingState::kInitializing;
  Eigen::Isometry3d camera_to_map = Eigen::Isometry3d::Identity();  // valid unless lost
  bool keyframe = false;
  bool rotation_only = false;  // too little parallax to triangulate this frame
  cv::Mat depth;               // CV_32F along the optical axis in map units, NaN = unknown
  cv::Mat confidence;          // CV_32F, same size, 0 where depth is unknown
};

// Which frame an input is, as a camera stamps its images: the rollout it belongs to
// (RolloutId) and its index there. The visual backend ignores it; the oracle looks the
// frame's ground truth up by it (ground_truth_source.h).
struct FrameStamp {
  uint64_t rollout = 0;
  int index = 0;
};

// What a backend gets per frame: what a real SLAM sees.
struct SlamInput {
  cv::Mat rgb;  // CV_8UC3 RGB
  FrameStamp stamp;
};

class SlamState;  // backend-specific, immutable once snapshotted

class Slam {
 public:
  virtual ~Slam() = default;
  virtual TrackedFrame track(const SlamInput& input) = 0;
  // An independent SLAM continuing from this one's current state.
  virtual std::unique_ptr<Slam> branch() const = 0;
  virtual std::shared_ptr<const SlamState> snapshot() const = 0;
  // Throws InputError when `state` came from another backend.
  virtual void restore(const std::shared_ptr<const SlamState>& state) = 0;
  // Keyframe clouds made since keyframe index `first` (0 = all), in map frame.
  virtual std::vector<KeyframeCloud> keyframeClouds(int first = 0) const = 0;
  virtual int keyframeCount() const = 0;
  // Every tracked frame's pose so far (lost frames repeat the last pose).
  virtual std::vector<Eigen::Isometry3d> trajectory() const = 0;
  virtual CameraIntrinsics intrinsics() const = 0;
};

class SlamState {
 public:
  virtual ~SlamState() = default;
};

}  // namespace valerant
