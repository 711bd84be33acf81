#pragma once
// Judges one branch from its frames (paper eqs. 6 and 7): collects per frame the floor
// sample, the central raw depth and, on keyframes, the points with their
// floor-normalised heights; at the end runs the point-cloud and depth collision tests
// (each only when enabled: the COL ablations) and reports SLAM loss. Coverage,
// progress and the failed-region test need the episode's grid and are added by Episode.
// Used by the in-process pipeline and by the collision_checker node alike.
//
// Floor not yet known (a branch that starts from an uninitialised SLAM, e.g. after the
// one-frame context or rotation-only commits): no height is read from a made-up floor.
// Frames before the branch's first accepted floor take that floor's camera-to-floor
// relation (normal and distance in the camera frame), propagated backwards exactly as
// RF propagates it forwards; the SLAM has one scale within a branch, so the relation
// holds there too. A translation whose branch never accepts a floor cannot be judged
// and is marked floor_unknown (inadmissible); rotations need no floor (eq. 6 exempts
// them and they do not advance for eq. 7).
//
// Committed points ([ours], collision.previous_steps, committed_points.h): the
// confident points of the latest committed steps are counted too, with heights from
// the branch's first floor (collision.committed_heights = own_floor: from their own
// keyframe's floor, as eq. 5 has it, where that keyframe had one); points already
// inside the body cylinder at the start are left out, so standing beside a wall does
// not block every move.
//
// Step-aware eq. 6 ([ours], collision.step_height > 0, step_support.h): the keyframe
// points take their heights from the branch's first floor too, not from their own
// keyframe's: the support the body climbs is one height along the branch, and a
// keyframe's floor fitted on a stair would move the datum from point to point.
//
// Free-space evidence ([ours], collision.see_through_frames, free_space_evidence.h):
// every frame's confident depth is kept (at half resolution), and before eq. 6 counts,
// the points at or above eta_low that enough of the branch's frames saw past are left
// out (see_through_points), the branch's own and the committed steps' alike.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/explore/body_reach.h"
#include "valerant/explore/branch_verdict.h"
#include "valerant/explore/committed_points.h"
#include "valerant/explore/depth_collision.h"
#include "valerant/explore/free_space_evidence.h"
#include "valerant/explore/point_cloud_collision.h"
#include "valerant/slam/slam.h"

namespace valerant {

class BranchCheck {
 public:
  // `committed`: CommittedPoints::points() (empty: none).
  BranchCheck(const Config& config, CommittedSteps committed);
  // `keyframe`: the keyframe cloud this frame made (null if none); `floor`: its floor.
  void add(const TrackedFrame& frame, const KeyframeCloud* keyframe, const FloorPlane& floor);
  size_t frames() const { return samples_.size(); }
  // The floor of every frame so far, unknown ones filled from the first known one
  // (all still unknown when no frame has a known floor).
  std::vector<FloorPlane> floors() const;
  // Collision fields, rotation_only, slam_lost, floor_unknown and prefix_frames of
  // the verdict.
  BranchVerdict finish(const std::string& candidate, bool rotation_only) const;

 private:
  struct KeyframePoints {
    size_t frame;
    std::vector<CloudPoint> points;
  };
  // Where the bodies of `floors` at `radius` can reach (body_reach.h) in the slab of every
  // point of the branch and the committed steps: the points outside are never counted,
  // so they are not copied. nullopt: no bound (keep every point).
  std::optional<ReachableBox> reachOfAll(const std::vector<FloorPlane>& floors, double radius) const;
  CollisionConfig config_;
  CommittedSteps committed_;
  double d_fwd_normalised_;
  std::vector<FloorPlane> samples_;
  std::vector<Eigen::Isometry3d> poses_;
  std::vector<double> central_depths_;
  std::vector<KeyframePoints> keyframes_;
  std::vector<DepthView> depth_views_;  // with collision.see_through_frames > 0
  double fov_x_deg_;                     // of depth_views_' images
  int first_lost_ = -1;  // first frame the SLAM lost track, -1 = never
};

}  // namespace valerant
