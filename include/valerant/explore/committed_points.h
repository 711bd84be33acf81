#pragma once
// The points of the latest committed steps that eq. 6 counts beside a branch's own
// ([ours], collision.previous_steps; BranchCheck). A camera looking forward does not
// see a wall right beside it, nor one it has turned away from, so a step that scrapes
// such a wall has almost none of its own points in the body cylinder: on oa_dm5 spawn 1
// a full `uw` grazed a pillar with 1 of the branch's points inside rho, which the SLAM
// had mapped two steps earlier. Every committed step continues the same SLAM map
// (branches restart from the committed state), so these points share the branch's
// frame and scale, up to drift. Kept per step, so that the oldest can be dropped: the
// count costs points x samples per branch. Only points with confidence >=
// collision.min_confidence (the eq. 6 cut) are kept.
//
// Each point also keeps its normalised height h from the floor of its own keyframe,
// which eq. 6 uses with collision.committed_heights = own_floor (as eq. 5 has it for the
// branch's own points; the default measures it from the branch's first floor). The
// depth prior scales each view by the map's units per metre of its moment, so a view
// whose scale came out 20 % small places the floor under its camera 0.2 eye heights
// high; its own floor, fitted on its own points, is off by the same factor and cancels
// it. From the branch's first floor such floor patches stand 0.19 to 0.33 eye heights
// high in a thin layer inside the body cylinder and reject clean translations: 1,005 to
// 1,447 points at the first samples of a `uw` on oa_dm5 spawn 1 (docs/committed_heights.md).
//
// A value: checkpoints copy it. The per-step point sets are immutable and shared by
// every copy, and are handed to the branches as they are: one merged copy per
// checkpoint cost up to 150 MB each with the depth prior's dense clouds.
#include <memory>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/geometry/floor_plane.h"
#include "valerant/slam/slam.h"

namespace valerant {

// One confident point of a committed step; h is NaN where its keyframe had no known
// floor (BranchCheck then measures it from the branch's first floor).
struct CommittedPoint {
  Eigen::Vector3f position;
  float h = 0;
  float confidence = 0;
};

// The kept steps' confident points, one immutable set per step, oldest first.
using CommittedSteps = std::vector<std::shared_ptr<const std::vector<CommittedPoint>>>;

class CommittedPoints {
 public:
  // Keeps the latest config.previous_steps steps (0: none).
  explicit CommittedPoints(const CollisionConfig& config);
  // One committed step: the keyframe clouds its branch made and their floors (one
  // each; BranchResult::keyframe_floors). Throws InputError when the counts differ.
  void add(const std::vector<KeyframeCloud>& keyframes, const std::vector<FloorPlane>& floors);
  // The kept steps' points, oldest step first; empty when none are kept.
  const CommittedSteps& points() const { return steps_; }
  int steps() const { return static_cast<int>(steps_.size()); }

 private:
  int steps_kept_;
  float min_confidence_;
  CommittedSteps steps_;
};

}  // namespace valerant
