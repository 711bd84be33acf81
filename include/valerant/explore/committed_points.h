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
// [ours] Carving (collision.carve_committed_views k > 0, docs/see_through.md): the visual
// depth scatters points into open space, and on oa_dm5 96 % of the points eq. 6 counted
// at its false collisions were committed ones, most of them floor read short, which the
// branch's own frames (see_through_frames) rarely look at. The committed keyframes did:
// each step's keyframe depth views are rebuilt from their clouds (depthViewOfCloud), and
// every kept point gathers free-space evidence (free_space_evidence.h) from the views of
// every step added while it is kept, its own step's included. A point seen through by k
// or more views, and by more than saw it there, is left out of points(). A floor point
// read h eye heights high is seen through by any view that sees the floor behind it
// once 1 / (1 - h) > 1 + tau (h > 0.23 at tau 0.3), at whatever distance: the ray from
// the eye through it meets the floor that much farther on.
//
// A value: checkpoints copy it. The per-step point sets are immutable and shared by
// every copy, and are handed to the branches as they are: one merged copy per
// checkpoint cost up to 150 MB each with the depth prior's dense clouds.
#include <memory>
#include <vector>

#include "valerant/common/camera.h"
#include "valerant/config/config.h"
#include "valerant/explore/free_space_evidence.h"
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
  // Keeps the latest config.previous_steps steps (0: none). `frame`: the intrinsics of
  // the frames the keyframes came from; carving needs them (an InputError naming the key without).
  explicit CommittedPoints(const CollisionConfig& config, const CameraIntrinsics& frame = {});
  // One committed step: the keyframe clouds its branch made and their floors (one
  // each; BranchResult::keyframe_floors). Throws InputError when the counts differ.
  void add(const std::vector<KeyframeCloud>& keyframes, const std::vector<FloorPlane>& floors);
  // The kept steps' points, oldest step first, less the carved ones; empty when none are kept.
  const CommittedSteps& points() const { return steps_; }
  int steps() const { return static_cast<int>(steps_.size()); }
  // Points of the kept steps that carving leaves out of points() (0 without carving).
  size_t carvedPoints() const;

 private:
  // What carving keeps of a step beside its points; immutable, shared by copies.
  struct Carving {
    std::shared_ptr<const std::vector<CommittedPoint>> all;          // every confident point
    std::shared_ptr<const std::vector<FreeSpaceEvidence>> evidence;  // per point of `all`
    std::shared_ptr<const std::vector<DepthView>> views;             // the step's keyframes'
  };
  // Adds the evidence of `views` to `carving`'s points; returns the step's points left.
  std::shared_ptr<const std::vector<CommittedPoint>> carve(Carving& carving, const std::vector<DepthView>& views) const;
  CollisionConfig config_;
  CameraIntrinsics view_;  // of the rebuilt depth views: half the frame's resolution
  CommittedSteps steps_;
  std::vector<Carving> carving_;  // one per kept step while carving, else empty
};

}  // namespace valerant
