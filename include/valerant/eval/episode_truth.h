#pragma once
// Ground-truth figures of one episode on the engine world (never fed back to the
// pipeline): penetrations of the committed frames, the share of the reachable floor
// the fused map observed, and how the collision verdicts agree with the in-solid truth.
//
// The SLAM map is tied to the BSP frame by a Sim(3) fitted (Umeyama) between the
// committed camera centres and their ground-truth centres. A trajectory that never
// translated (rotations in place only) has no such fit; then the first pose ties the
// frames (rotation and position) and the floor gives the scale: the anchor's
// camera-to-floor distance in map units against the engine's eye height. Floor points of the map
// (|h| < eta_low) then mark 1 m cells. A reachable 1 m cell counts as observed when a
// floor point falls in it within half a step height of a reachable floor height there.
// The same test on the committed frames' true depth gives the floor in view of the
// path, whatever the SLAM made of it.
#include <Eigen/Geometry>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "valerant/common/camera.h"
#include "valerant/eval/trajectory_metrics.h"
#include "valerant/explore/episode.h"
#include "valerant/world/quake3/reachable_floor.h"

namespace valerant {

struct EpisodeTruth {
  int committed_frames = 0;
  // Frames of the final trajectory that penetrate the world (FrameTruth::in_solid): the
  // union of the two reasons below, so at most their sum.
  int penetrating_frames = 0;
  int penetrating_frames_in_solid = 0;       // ... whose player hull is inside solid
  int penetrating_frames_outside_world = 0;  // ... whose hull centre is outside the playable world
  // ... whose only reason is a hull in nodraw player-clip brushes alone: volumes that
  // stop the player but draw nothing, so no camera-based test can see them (kaos2 spawn 0 with
  // the depth prior: every one of its 706 frames; docs/depth_prior.md).
  int penetrating_frames_clip_only = 0;
  // In-solid frames of committed steps that a rewind later discarded: committed once,
  // so counted, but no longer part of the trajectory (or of penetrating_frames).
  int discarded_penetrating_frames = 0;
  double reachable_m2 = 0;
  double observed_reachable_m2 = 0;
  double observed_reachable_percent = 0;
  // The reachable floor the final trajectory's committed frames had in view: the
  // union of ReachableCells::inViewOf over the frames that keep their depth (every
  // kCommittedDepthStride-th), at the oracle SLAM's cloud stride. Against the observed
  // figure it splits a short coverage into where the agent went (this) and what the
  // map made of what it saw (observed / in view). Frames of steps a rewind discarded
  // are not in it, though with dead_pocket.keep_map their keyframes stay in the map.
  double in_view_reachable_m2 = 0;
  double in_view_reachable_percent = 0;
  // observed_reachable_percent of the final map's keyframes up to each step (one per
  // history entry; a rewound step's value counts the keyframes that replaced its own).
  std::vector<double> observed_percent_by_step;
  bool aligned = false;          // false: the trajectory was too short to fit a Sim(3)
  bool floor_aligned = false;    // not aligned, but tied to the world by the first pose and the floor
  Sim3 map_to_world_metres;      // the fitted alignment (identity when neither)
  double alignment_scale = 0;    // metres per map unit
  // Residual of the camera centres after the Sim(3) fit (ATE), and as a share of the
  // path length; NaN unless `aligned` (a floor tie fits no path), null in report.json.
  double alignment_rmse_m = std::numeric_limits<double>::quiet_NaN();
  double ate_percent = std::numeric_limits<double>::quiet_NaN();
  // Roll and pitch error of the committed frames under the alignment (tiltErrorsDeg, up
  // the BSP's +z), median and 90th percentile; NaN unless aligned or floor-tied.
  double tilt_median_deg = std::numeric_limits<double>::quiet_NaN();
  double tilt_p90_deg = std::numeric_limits<double>::quiet_NaN();
  int verdicts = 0;              // candidate evaluations with ground truth
  int truly_colliding = 0;       // candidates whose frames penetrate (in solid or outside the world)
  int predicted_colliding = 0;   // candidates rejected by a collision test
  int false_rejections = 0;      // predicted but not truly colliding
  int missed_collisions = 0;     // truly colliding but not predicted
};

// Penetrating frames of a run of frames, with each reason counted on its own.
struct PenetrationCounts {
  int frames = 0;         // in_solid: the union of the two below
  int in_solid = 0;       // hull_in_solid
  int outside_world = 0;  // outside_world
  int clip_only = 0;      // hull_in_clip_only and not outside_world: nothing visible entered
};
PenetrationCounts countPenetrations(const std::vector<FrameTruth>& truth);

// In-solid (penetrating) frames the step committed (0 for a stall).
int stepInSolidFrames(const StepRecord& step);

// The candidate has the engine's truth and none of its frames entered solid.
bool staysOutOfSolid(const CandidateRecord& candidate);

// A committed step that penetrated the world (the player hull inside solid, or its
// centre outside the playable world), with what its collision tests saw: the figures
// one needs to tell why the tests let it through.
struct PenetrationEvent {
  int step = 0;
  std::string candidate;      // the committed candidate, e.g. "jw" or a prefix "jw@20"
  int frames = 0;             // its in-solid (penetrating) frames
  int frames_in_solid = 0;    // ... whose player hull is inside solid
  int frames_outside_world = 0;  // ... whose hull centre is outside the playable world
  int frames_clip_only = 0;      // ... whose hull is in invisible player-clip brushes only
  int first_frame = 0;        // 0-based index of the first one within the step
  int occupied_max = 0;       // most points in the body cylinder at one sample (eq. 6)
  double min_near_ratio = 0;  // smallest central depth / camera height (eq. 7)
};
// Every committed step of `history` with in-solid frames, kept or later discarded.
std::vector<PenetrationEvent> penetrationEvents(const std::vector<StepRecord>& history);
// In-solid frames of every committed step in `history`, kept or later discarded.
int committedInSolidFrames(const std::vector<StepRecord>& history);

// The reachable floor as 1 m cells split into storeys (two step heights high), with
// the floor heights found in each cell: what "observed" is counted against.
class ReachableCells {
 public:
  using Cell2 = std::pair<int, int>;             // 1 m cell, BSP x and y
  using CellStorey = std::pair<Cell2, int>;      // a cell on one storey
  explicit ReachableCells(const quake3::ReachableFloor& reachable);
  size_t count() const { return count_; }        // (cell, storey) pairs: the reachable m2
  // The pairs the floor points (|h| < `band`) of `keyframe` observe, its points taken to
  // the BSP frame in metres by `map_to_world`.
  std::set<CellStorey> observedBy(const FusedKeyframe& keyframe, const Sim3& map_to_world, double band) const;
  // The pairs the true depth of one committed frame sees: every `stride`-th pixel per
  // axis, taken to the BSP frame by the frame's true pose, that lies less than
  // `band_units` over or under the frame's own floor (the test observedBy applies to a
  // map point's h) and within half a step height of a reachable floor height. No SLAM
  // in between: what a perfect map built from these frames would observe. None for a
  // frame without depth.
  std::set<CellStorey> inViewOf(const FrameTruth& frame, const CameraIntrinsics& k, double band_units,
                                int stride) const;

 private:
  static int storeyOf(float z_units);
  // The reachable pair a point of the BSP frame (game units) lies on: its 1 m cell, if
  // a reachable floor height there is within half a step height of it.
  std::optional<CellStorey> floorAt(const Eigen::Vector3d& world_units) const;
  std::map<Cell2, std::vector<float>> heights_;
  size_t count_ = 0;
};

// How the episode's map frame is tied to the BSP frame (metres): the Sim(3) fit of the
// committed camera centres, or, when they never translated, the first pose and the floor.
struct EpisodeAlignment {
  bool aligned = false;        // a Sim(3) was fitted
  bool floor_aligned = false;  // not aligned, tied by the first pose and the floor
  Sim3 map_to_world_metres;    // identity when neither
  double rmse_m = std::numeric_limits<double>::quiet_NaN();  // ATE of the whole committed path (aligned only)
  double ate_percent = std::numeric_limits<double>::quiet_NaN();  // ... as a share of its length
};
EpisodeAlignment alignEpisode(const Episode& episode);

EpisodeTruth evaluateEpisodeTruth(const Episode& episode, const quake3::ReachableFloor& reachable);

}  // namespace valerant
