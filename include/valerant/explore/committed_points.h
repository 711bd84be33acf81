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
// A value: checkpoints copy it. The per-step point sets are immutable and shared by
// every copy, and are handed to the branches as they are: one merged copy per
// checkpoint cost up to 150 MB each with the depth prior's dense clouds.
#include <memory>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/slam/slam.h"

namespace valerant {

// The kept steps' confident points, one immutable set per step, oldest first.
using CommittedSteps = std::vector<std::shared_ptr<const std::vector<CloudPoint>>>;

class CommittedPoints {
 public:
  // Keeps the latest config.previous_steps steps (0: none).
  explicit CommittedPoints(const CollisionConfig& config);
  // One committed step: the keyframe clouds its branch made.
  void add(const std::vector<KeyframeCloud>& keyframes);
  // The kept steps' points, oldest step first; empty when none are kept.
  const CommittedSteps& points() const { return steps_; }
  int steps() const { return static_cast<int>(steps_.size()); }

 private:
  int steps_kept_;
  float min_confidence_;
  CommittedSteps steps_;
};

}  // namespace valerant
