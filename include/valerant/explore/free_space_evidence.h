#pragma once
// [ours] Free-space evidence against eq. 6's points (collision.see_through_frames,
// branch_check.h). The visual depth scatters points into open space, most of them
// close in front of the camera that made them; eq. 6 counts each one as an obstacle,
// and on the visual runs most rejections of translations that stay out of solid come
// from them (docs/see_through.md). A point some camera looked *past* is free space:
// the ray to its pixel went on to a surface beyond it (a free-space violation, as in
// visibility-based depth-map fusion, Merrell et al. 2007, and OctoMap's misses).
// For a point p and each depth view j in which p lies in front of the camera (z > 0)
// and projects inside the image onto a known depth d:
//   through   d > (1 + tau) z      the view saw past p
//   support   |d - z| <= tau z     the view saw a surface where p is
//   (d < (1 - tau) z: p hidden behind a nearer surface, no evidence either way)
// p is seen through when through >= min_frames and through > support: a real wall's
// point that one noisy view saw past is still held by the views that saw it.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <vector>

#include "valerant/common/camera.h"
#include "valerant/slam/slam.h"

namespace valerant {

struct DepthView {
  Eigen::Isometry3d map_to_camera = Eigen::Isometry3d::Identity();
  cv::Mat depth;  // CV_32F along the optical axis, NaN where unknown or not confident
};

struct FreeSpaceEvidence {
  int through = 0;
  int support = 0;
  bool seenThrough(int min_frames) const { return min_frames > 0 && through >= min_frames && through > support; }
};

// `k`: the intrinsics of the views' depth images (all one size); `tau` > 0.
FreeSpaceEvidence freeSpaceEvidence(const Eigen::Vector3d& p, const std::vector<DepthView>& views,
                                    const CameraIntrinsics& k, double tau);

// A depth view of a tracked frame's depth: the pixels under `min_confidence` unknown,
// shrunk by `shrink` (nearest pixel: the visual depth is swept at half resolution, so
// a shrink of 2 keeps every value it measured).
DepthView depthViewOf(const Eigen::Isometry3d& camera_to_map, const cv::Mat& depth, const cv::Mat& confidence,
                      double min_confidence, int shrink);

// A keyframe's depth view rebuilt from its cloud (committed steps keep their points, not
// their depth images): each point with confidence >= `min_confidence` is projected into
// the keyframe's own camera with intrinsics `view` and the nearest one kept per pixel.
// The visual clouds hold one point per swept pixel (every second pixel a side), so at
// half the frame's resolution this gives back the confident depth the view measured.
DepthView depthViewOfCloud(const KeyframeCloud& keyframe, const CameraIntrinsics& view, double min_confidence);

}  // namespace valerant
