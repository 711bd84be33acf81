#pragma once
// Judges one branch from its frames (paper eqs. 6 and 7): collects per frame the floor
// sample, the central raw depth and, on keyframes, the points with their
// floor-normalised heights; at the end runs the point-cloud and depth collision tests
// (each only when enabled: the COL ablations) and reports SLAM loss. Coverage,
// progress and the failed-region test need the episode's grid and are added by Episode.
// Used by the in-process pipeline and by the collision_checker node alike.
#include <string>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/explore/branch_verdict.h"
#include "valerant/explore/depth_collision.h"
#include "valerant/explore/point_cloud_collision.h"
#include "valerant/slam/slam.h"

namespace valerant {

class BranchCheck {
 public:
  explicit BranchCheck(const Config& config);
  // `keyframe`: the keyframe cloud this frame made (null if none); `floor`: its floor.
  void add(const TrackedFrame& frame, const KeyframeCloud* keyframe, const FloorPlane& floor);
  size_t frames() const { return samples_.size(); }
  // Collision fields, rotation_only and slam_lost of the candidate's verdict.
  BranchVerdict finish(const std::string& candidate, bool rotation_only) const;

 private:
  CollisionConfig config_;
  double d_fwd_normalised_;
  std::vector<FloorPlane> samples_;
  std::vector<DepthSample> depth_samples_;
  std::vector<HeightedPoint> points_;
  bool lost_ = false;
};

}  // namespace valerant
