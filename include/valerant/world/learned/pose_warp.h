#pragma once
// The pose_anchor warp's geometry (world.learned.warp: pose_anchor; the same arithmetic
// as learn/valerant_learn/pose_warp.py, whose text explains it): the commanded camera
// motion, turn and translation, applied exactly through each pixel's depth, so that the
// translation's parallax is geometry and the net's flow only a residual.
//
// A CameraPose is x, y (metres) on the floor plane of the rollout's first anchor (that
// camera at 0, 0 heading 0: x ahead, y to its left), yaw (left positive) and pitch (down
// positive) in degrees; the first anchor is taken as level and heights never change.
//
//   poseSampling: pixel p of the next camera M, ray d = ((x + 0.5 - cx) / fx,
//     (y + 0.5 - cy) / fy, 1), lies at a z' + t in the newest camera N (a = R d, (R, t)
//     taking M's optical frame to N's); from the rotation's position s_0 = proj(a),
//     kPoseFixedPointIterations times:
//       Z = Z_N(s_k) (bilinear, border), z' = (Z - t_z) / a_z, s_k+1 = proj(a z' + t)
//     in_view: a_z > 0, z' > 0 and s inside the image; rays behind N parked at its centre.
//   depthInCamera: the depth, seen from a pose, of the anchor's pixels at given
//     coordinates at the anchor's depth (clamped to at least kMinDepthM).
#include <opencv2/core.hpp>

#include "valerant/common/camera.h"
#include "valerant/world/action_sequence.h"
#include "valerant/world/learned/warp_sampling.h"

namespace valerant {

constexpr int kPoseFixedPointIterations = 3;
constexpr double kMinDepthM = 0.05;   // depths are clamped to at least this, so that points project
constexpr double kSkyDepthM = 80.0;   // the depth prior's sky; a missing depth is the sky
constexpr double kUnitsPerMetreWorld = 32.0;  // MotionStep's game units

struct CameraPose {
  double x_m = 0, y_m = 0, yaw_deg = 0, pitch_deg = 0;
};

// The pose after `motion`, as the engine moves (camera_kinematics.cpp): turn first, then
// forward and strafe (to the right) along the new heading.
CameraPose advancePose(const CameraPose& pose, const MotionStep& motion);

// The pose_anchor warp's part of AnchorState (anchor_warp.h): the anchor frame's depth
// (CV_32F metres along its optical axis) and pose, the newest frame's pose, the camera.
struct PoseGeometry {
  cv::Mat depth;
  CameraPose anchor_pose, pose;
  CameraIntrinsics camera;

  // The geometry of an anchor seen at `depth_m` (CV_32F; not finite, as a missing true
  // depth's NaN: the sky; at least kMinDepthM), both poses the first anchor's (zeros).
  static PoseGeometry start(const cv::Mat& depth_m, const CameraIntrinsics& camera);
  // The newest frame's depth of pixels whose anchor coordinates are `coords` (CV_32FC2).
  cv::Mat depthOf(const cv::Mat& coords) const;
  // This geometry with the newest pose advanced by `motion`.
  PoseGeometry moved(const MotionStep& motion) const;
  // The geometry whose anchor is the newest frame, its pixels at anchor coordinates
  // `coords`: their depth carried over (depthOf), its pose the newest.
  PoseGeometry reanchored(const cv::Mat& coords) const;
};

// Where each pixel of the camera at `next_pose` looks in the newest frame, whose depth is
// `newest_depth` (CV_32F metres) and pose `newest_pose` (header text).
WarpSampling poseSampling(const cv::Mat& newest_depth, const CameraPose& newest_pose, const CameraPose& next_pose,
                          const CameraIntrinsics& camera);

// CV_32F: the depth in the camera at `pose` of the points of the anchor's pixels at
// `coords` (CV_32FC2), the anchor at `anchor_pose` seeing them at `anchor_depth` (CV_32F,
// sampled bilinearly with the border replicated); at least kMinDepthM.
cv::Mat depthInCamera(const cv::Mat& anchor_depth, const cv::Mat& coords, const CameraPose& anchor_pose,
                      const CameraPose& pose, const CameraIntrinsics& camera);

}  // namespace valerant
