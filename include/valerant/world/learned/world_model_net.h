#pragma once
// One step of the learned world model: an ONNX net (trained in learn/) run on the CPU by
// OpenCV's DNN module on one thread. A single-step, deterministic, action-conditioned
// next-frame predictor, run autoregressively by its callers.
//
// The model's contract (docs/world_model.md, section "Backend"):
//   input  "frames_and_motion" ("frames_motion_and_pose_warp" for pose_anchor, so that a
//          model of one warp cannot be run as another's) float32 [1, 3K+4+E, H, W]: the K most recent frames, oldest
//          first, each as R,G,B planes in [0,1] (frame k is channels 3k..3k+2), then four
//          constant planes with the commanded motion of the frame to produce, the raw
//          MotionStep values forward_units, strafe_units, yaw_deg, pitch_deg (the net
//          scales them itself), then the warp's E extra planes;
//   output "warp_and_fill" float32 [1, 6, H, W]: flow dx, dy in pixels, mask m in [0,1],
//          fill R,G,B in [0,1].
// Three warps (world.learned.warp); the configuration must name the one the model was
// trained with (its model card does):
//   last_frame (models v1, v2; E = 0): the next frame is warpAndFill() of the newest frame;
//   rotation_anchor (v3; E = 4: the newest frame sampled at rotationSampling()'s positions,
//          R,G,B, and their in_view mask): the flow is added to those positions and the
//          next frame is anchorStep() (anchor_warp.h);
//   pose_anchor (E = 4: the same planes at poseSampling()'s positions, pose_warp.h): as
//          rotation_anchor with the commanded turn and translation through each pixel's
//          depth; the first anchor's depth is the depth prior's prediction on it.
// A pose_anchor model's input has its own name, so each of the two anchor warps refuses
// the other's model at load; last_frame and rotation_anchor tell by the input's channels.
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>
#include <string>
#include <vector>

#include "valerant/common/camera.h"
#include "valerant/common/depth_prior.h"
#include "valerant/world/action_sequence.h"
#include "valerant/world/learned/anchor_warp.h"

namespace valerant {

// next(x,y) = m * last(x+dx, y+dy) + (1-m) * fill(x,y), `last` sampled bilinearly with
// border replication, clamped to [0,1] and rounded to 8 bits. `last`: CV_8UC3 RGB;
// `flow`: CV_32FC2 (dx, dy) in pixels; `mask`: CV_32F; `fill`: CV_32FC3 RGB in [0,1];
// all of one size. Returns CV_8UC3 RGB of that size.
cv::Mat warpAndFill(const cv::Mat& last, const cv::Mat& flow, const cv::Mat& mask, const cv::Mat& fill);

enum class WorldWarp { kLastFrame, kRotationAnchor, kPoseAnchor };

// "last_frame", "rotation_anchor" or "pose_anchor" (world.learned.warp); throws
// InputError naming the value otherwise.
WorldWarp parseWorldWarp(const std::string& name);
const char* worldWarpName(WorldWarp warp);

class WorldModelNet {
 public:
  // Loads the ONNX file at `path` for frames of `width` x `height` seen with a horizontal
  // field of view of `fov_x_deg` (square pixels, principal point at the centre: the
  // rotation warp's camera), `context_frames` (K) frames of context and `warp`, and runs
  // one probe forward on zeros. `depth_prior`: the depth of the first anchor, which
  // pose_anchor needs (the prior it was trained with, models/world_model.md), else unused.
  // Throws InputError naming `path` when it is missing, unreadable or not a model of this
  // contract (its input named for another warp included), or pose_anchor has no prior.
  WorldModelNet(const std::string& path, int width, int height, int context_frames, WorldWarp warp,
                double fov_x_deg, std::shared_ptr<const DepthPrior> depth_prior = nullptr);

  // The anchor state of a rollout whose newest context frame is `frame_rgb8` (CV_8UC3,
  // width() x height()): AnchorState::start, with pose_anchor's geometry from the depth
  // prior's prediction on the frame (resized to the net's size if the prior's differs).
  AnchorState startAnchor(const cv::Mat& frame_rgb8) const;

  // `context`: exactly contextFrames() CV_8UC3 RGB frames of width() x height(), oldest
  // first; `anchor`: the anchor warps' state of the same rollout (started with
  // startAnchor() at the newest context frame, then passed to every step; the last_frame
  // warp leaves it alone). Returns the next frame, CV_8UC3 RGB, width() x
  // height(). Throws InputError on a wrong context.
  cv::Mat next(const std::vector<cv::Mat>& context, const MotionStep& motion, AnchorState& anchor);

  int width() const { return camera_.width; }
  int height() const { return camera_.height; }
  int contextFrames() const { return context_frames_; }
  WorldWarp warp() const { return warp_; }
  const std::string& path() const { return path_; }

 private:
  // Input channels: 3K + 4 + the warp's extra planes.
  int inputChannels() const;
  // One forward pass of a [1,inputChannels(),H,W] blob; the [1,6,H,W] output as its own copy.
  // Throws InputError naming the model when it cannot run or gives another shape.
  cv::Mat forward(const cv::Mat& blob);

  std::string path_;
  CameraIntrinsics camera_;
  int context_frames_;
  WorldWarp warp_;
  std::shared_ptr<const DepthPrior> depth_prior_;
  cv::dnn::Net net_;
};

}  // namespace valerant
