#pragma once
// The learned world model's anchor warps (world.learned.warp: rotation_anchor or
// pose_anchor; the same arithmetic as learn/valerant_learn/world_warp.py, whose text
// explains it): the commanded rotation (rotation_anchor) or the whole commanded motion
// through each pixel's depth (pose_anchor, pose_warp.h) is applied exactly, the net adds
// a residual flow, and every pixel is sampled once from a sharp anchor frame through a
// coordinate map, so detail does not blur away step by step.
//
//   s       = geometry positions + flow          (where pixel p looks in the newest frame)
//   coords' = coords(s), valid' = valid(s)       (bilinear; valid is 0 outside the image)
//   warped  = anchor(coords') where valid' >= kValidMin, else newest(s)
//   next    = mask * warped + (1 - mask) * fill
//   valid   = valid' >= kValidMin and mask >= 0.5
// and when fewer than kReanchorFraction of the pixels stay valid, next becomes the anchor
// (with pose_anchor its depth carried over: PoseGeometry::reanchored).
//
// Sampling is bilinear in pixel-index coordinates (warp_sampling.h).
#include <opencv2/core.hpp>
#include <optional>

#include "valerant/common/camera.h"
#include "valerant/world/action_sequence.h"
#include "valerant/world/learned/pose_warp.h"
#include "valerant/world/learned/warp_sampling.h"

namespace valerant {

constexpr float kValidMin = 0.999f;        // a sampled validity this high is an anchor pixel
constexpr double kReanchorFraction = 0.6;  // below this share of valid pixels, re-anchor

// Where each pixel of the next frame looks in the newest frame when the camera only
// rotates by the motion's yaw (left positive) and pitch (down positive), for a camera of
// `camera`'s size and intrinsics (cx, cy from the image corner: pixel i spans [i, i+1)).
// The ray d = ((x + 0.5 - cx) / fx, (y + 0.5 - cy) / fy, 1) (x right, y down, z ahead) is
// turned by the pitch about x, then by the yaw about the vertical y:
//   pitch b: (x, y cos b + z sin b, -y sin b + z cos b)
//   yaw a:   (x cos a - z sin a, y, x sin a + z cos a)
// and projected back. Exact when the newest frame's own pitch is zero. Rays behind the
// camera are parked at the image centre with in_view 0 (in_view: the ray is ahead of the
// newest camera and inside its image).
WarpSampling rotationSampling(const MotionStep& motion, const CameraIntrinsics& camera);

struct AnchorState {
  cv::Mat anchor;  // CV_32FC3 RGB in [0,1]: the frame the coordinates point into
  cv::Mat coords;  // CV_32FC2: where each pixel of the newest frame lies in the anchor
  cv::Mat valid;   // CV_32F, 0 or 1: the newest frame's pixel is anchor(coords)
  std::optional<PoseGeometry> geometry;  // pose_anchor's depth and poses; none for rotation_anchor

  // The state whose anchor is `frame_rgb8` (CV_8UC3) itself: identity coordinates, all
  // valid; with `geometry` (pose_anchor) the anchor's depth and poses.
  static AnchorState start(const cv::Mat& frame_rgb8, std::optional<PoseGeometry> geometry = std::nullopt);
};

// One step of the warp (header text). `newest_rgb8`: the newest frame, CV_8UC3;
// `positions`: CV_32FC2; `mask`: CV_32F; `fill`: CV_32FC3 RGB in [0,1], all of one size;
// `moved`: for pose_anchor the state's geometry moved to the next frame
// (PoseGeometry::moved), none for rotation_anchor. Returns the next frame, CV_8UC3 RGB
// (clamped to [0,1], rounded to 8 bits), and moves `state` on. The state's matrices are
// replaced, never written into: a checkpoint may share them.
cv::Mat anchorStep(AnchorState& state, const cv::Mat& newest_rgb8, const cv::Mat& positions, const cv::Mat& mask,
                   const cv::Mat& fill, const std::optional<PoseGeometry>& moved = std::nullopt);

}  // namespace valerant
