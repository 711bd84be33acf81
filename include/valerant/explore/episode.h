#pragma once
// The exploration loop (paper section 3.2), without ROS. Each
// step: a synchronised checkpoint of world and branch pipeline (SLAM, floor); five
// candidate rollouts from the committed state, each reconstructed and judged by the
// pipeline; coverage and progress on the episode's grid; the argmax of eq. 2 over
// admissible candidates (asked of a BranchSelector) is committed (its rollout and
// SLAM branch are reused: both backends are deterministic) and fused into the map; a
// dead pocket rewinds to an earlier checkpoint and grows the failed-region memory
// (eq. 8). When none of the five translations is admissible, the clean prefixes of the
// rejected ones are judged too and the choice is made again ([ours], clean_prefix.h);
// then, while still none is, shorter translations and turns ([ours], roomActionRounds).
// With policy.goal_move, every step also judges the move along the path to the nearest
// frontier ([ours], goal_move.h).
// Every candidate also gets the whole-level terms G and O (docs/whole_level.md).
// [ours] With collision.turn_contact_points, a turn in place is inadmissible while the
// camera stands where the last committed translation ended with that many points in
// eq. 6's body cylinder: a graze can leave the camera inside the brush (seeing out
// through its back faces), and eq. 6 exempts the turns (docs/inside_brush.md). With
// collision.turn_start_points, likewise while that many committed points stand inside
// the body cylinder at the turn's start (docs/pockets.md).
// [ours] With dead_pocket.ban_rewound_headings, a translation from a state a rewind went
// back to is inadmissible where it heads as a walk that led from there into the pocket
// did (rewound_headings.h).
// The same step code runs with in-process components (valerant_explore) and with the
// ROS graph's proxies (the explorer node): one code path, the same decisions.
#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/explore/branch_pipeline.h"
#include "valerant/explore/branch_selector.h"
#include "valerant/explore/failed_region_memory.h"
#include "valerant/explore/loop_closure.h"
#include "valerant/explore/rewind_controller.h"
#include "valerant/explore/rewound_headings.h"
#include "valerant/geometry/coverage_grid.h"
#include "valerant/geometry/frontier_distance.h"
#include "valerant/map/map_fusion.h"
#include "valerant/slam/slam.h"
#include "valerant/world/world_model.h"

namespace valerant {

// Per-candidate facts kept for reports and drawings.
struct CandidateRecord {
  BranchVerdict verdict;
  std::vector<Eigen::Vector3d> centres;  // map frame
  std::vector<FrameTruth> truth;         // ground truth of its frames, without depth (engine only; kept_truth.h)
};

struct StepRecord {
  int step = 0;                // 1-based exploration step (stalls count, rewinds do not)
  uint64_t checkpoint = 0;     // synchronised checkpoint taken before the step
  std::vector<CandidateRecord> candidates;
  int chosen = -1;             // index into candidates, -1 on a stall
  bool rewind = false;
  bool rewind_stagnant = false;  // [ours] declared by the stagnant-pocket rule (rewind_controller.h)
  uint64_t rewind_to = 0;
  int discarded_steps = 0;
  size_t map_keyframes = 0;    // keyframes in the global map after the step
  int committed_steps = 0;     // committed steps of the kept path after the step (a rewind lowers it)
  int new_floor_cells = 0;     // coverage-grid floor cells the step observed first
  bool drop = false;           // a committed translation that ended dead_pocket.drop_height or more below its start
  bool ended_in_start_cell = false;  // a committed translation that ended in the grid cell it started in
  int failed_forgotten = 0;    // [ours] cells of F forgotten after the step (dead_pocket.forget_failed_when_trapped)
  int rewind_reached_past = 0; // [ours] anchors the step's rewind passed over as known pockets (dead_pocket.reach_past_known_pocket)
  int way_back_freed = 0;      // [ours] cells of F on the kept path the step's rewind freed (dead_pocket.free_way_back)
  // The whole-level goal at the step's start (frontier_distance.h), whatever policy.goal_weight:
  // goal frontier cells, and the path distance D (cells) from the agent to the nearest one,
  // over walkable cells outside F and ignoring F; -1 where none is reachable.
  int goal_frontiers = 0;
  double goal_distance = -1, goal_distance_without_failed = -1;
  StageSeconds seconds;
  double wall_seconds = 0;
};

class Episode {
 public:
  // In this process (LocalBranchPipeline, a SLAM of config.slam.backend): feeds it the
  // world's context (the single starting screenshot) and decides with selectBranch().
  Episode(WorldModel& world, const Config& config);
  // With any pipeline and selector (e.g. the ROS graph's proxies); both outlive it.
  Episode(WorldModel& world, BranchPipeline& pipeline, BranchSelector& selector, const Config& config);

  StepRecord step();
  // The budget of committed steps is spent, the step cap is reached, or the episode is
  // stuck: a stall that no rewind can ever follow. A stall leaves world, SLAM, map and
  // F as they were, so every later step would judge the same rollouts the same way.
  bool finished() const;
  bool stuck() const { return stuck_; }
  void runUntilDone(const std::function<void(const StepRecord&)>& on_step, const std::atomic<bool>* stop = nullptr);

  int committedSteps() const { return committed_steps_; }
  int rewinds() const { return rewinder_.rewinds(); }
  const MapFusion& map() const { return map_; }
  const CoverageGrid& grid() const { return *grid_; }
  const FailedRegionMemory& failed() const { return failed_; }
  // The whole-level goal from `start`: F, less `start`, blocks its paths, or with
  // dead_pocket.cross_failed holds no goal frontier.
  FrontierDistance goalFrom(const Cell& start) const;
  const std::vector<Eigen::Isometry3d>& trajectory() const { return trajectory_; }  // committed frames
  // Ground truth of the committed frames; depth only every kCommittedDepthStride-th (kept_truth.h).
  const std::vector<FrameTruth>& truth() const { return truth_; }
  const std::vector<StepRecord>& history() const { return history_; }
  double anchorEyeHeight() const { return anchor_floor_.cameraHeight(); }  // kappa_0, map units
  // What the coverage grid is anchored on: the start floor and the start heading.
  const FloorPlane& gridAnchor() const { return anchor_floor_; }
  const Eigen::Vector3d& gridHeading() const { return anchor_heading_; }
  const Config& config() const { return config_; }
  // The committed keyframes' loop closure (loop_closure.h); null when it is off.
  const LoopClosure* loopClosure() const { return loop_closure_ ? &*loop_closure_ : nullptr; }
  // What the player sees now: the last committed frame (RGB; empty before any frame).
  cv::Mat currentView() const;

 private:
  struct Candidates {  // one step's judged candidates, index-aligned
    std::vector<std::string> names;
    std::vector<BranchResult> results;
    std::vector<std::vector<Eigen::Vector3d>> centres;  // committed start, then one per frame
    std::vector<BranchVerdict> verdicts;
  };
  struct Saved {
    CoverageGrid grid;
    size_t map_marker, trajectory_size;
    int committed_steps;
    std::optional<LoopClosure> loop_closure;
    int contact_points;
    std::optional<double> last_turn_deg;
  };
  // Uses `pipeline` and `selector` when given, else the owned ones.
  Episode(WorldModel& world, std::unique_ptr<BranchPipeline> own_pipeline, std::unique_ptr<BranchSelector> own_selector,
          BranchPipeline* pipeline, BranchSelector* selector, const Config& config);
  // Rolls out, reconstructs and scores `names` from the committed state into `out`.
  // `later`: names a later round of the step may judge; where one begins with the same
  // frames as a candidate here, the pipeline may keep that candidate's branch there.
  void judge(const std::vector<std::string>& names, const std::vector<std::string>& later, const Cell& start_cell,
             StepRecord& record, Candidates& out);
  // The clean prefixes (clean_prefix.h) worth judging after the first choice: none
  // while one of the paper's translations is admissible.
  std::vector<std::string> cleanPrefixes(const Candidates& judged) const;
  // The cells no path or ray of the whole-level terms may cross: F, less the start cell;
  // none with dead_pocket.cross_failed.
  std::set<Cell> blockedFrom(const Cell& start) const;
  // The goal figures of a step starting in `start` (StepRecord::goal_*).
  void recordGoal(const Cell& start, StepRecord& record) const;
  // [ours] Actions that fit the room (policy.short_translation_frames, short_turn_frames,
  // open_turn; docs/whole_level.md): rounds judged in order while no translation is
  // admissible: each short length's uw, jw, lw, then the short and open turns.
  std::vector<std::vector<std::string>> roomActionRounds() const;
  // [ours] The goal move's key string (policy.goal_move, goal_move.h); empty when it is
  // off or there is no move along a path to a frontier.
  std::optional<std::string> goalMoveAction() const;
  // Holds the verdicts of judged[first..] to their clean prefix to their last frame
  // (BranchVerdict::short_unclear): actions that end in front of walls by design.
  static void holdToClearEnd(Candidates& judged, size_t first);
  // The turn of the open-turn candidate, degrees left: toward the goal's waypoint
  // (frontier_distance.h) when it lies off the heading, else to the longest free ray.
  std::optional<double> openTurnDeg() const;
  // Fuses the keyframes of a result whose floor is known; returns how many.
  size_t fuseKnown(const BranchResult& result);
  void anchorGrid(bool reliable_floor);
  void markGrid(const FusedKeyframe& keyframe);
  // The coverage grid made afresh on its anchor from the trajectory and the map.
  void rebuildGrid();
  void commit(const BranchResult& chosen, const std::vector<Eigen::Vector3d>& centres);
  void rewind(const RewindDecision& decision, StepRecord& record);
  void release(const std::vector<uint64_t>& checkpoints);

  WorldModel& world_;
  std::unique_ptr<BranchPipeline> own_pipeline_;  // set by the in-process constructor
  std::unique_ptr<BranchSelector> own_selector_;
  BranchPipeline& pipeline_;
  BranchSelector& selector_;
  Config config_;
  double d_fwd_normalised_;
  std::optional<CoverageGrid> grid_;
  FloorPlane anchor_floor_;
  Eigen::Vector3d anchor_heading_ = Eigen::Vector3d::UnitX();
  bool anchored_on_reliable_floor_ = false;
  MapFusion map_;
  FailedRegionMemory failed_;
  RewindController rewinder_;
  // [ours] Walks rewound out of, by the state they left (dead_pocket.ban_rewound_headings).
  // Knowledge gained across rewinds, so no checkpoint restores it.
  RewoundHeadings rewound_;
  bool stuck_ = false;
  std::map<uint64_t, Saved> saved_;
  std::vector<Eigen::Isometry3d> trajectory_;
  std::vector<FrameTruth> truth_;
  std::vector<StepRecord> history_;
  std::optional<LoopClosure> loop_closure_;  // map and trajectory are in its corrected frame
  int committed_steps_ = 0, steps_ = 0;
  // [ours] Eq. 6's count at the last frame of the last committed translation: the
  // camera still stands there through the turns in place that follow, which
  // collision.turn_contact_points holds to it (docs/inside_brush.md).
  int contact_points_ = 0;
  // [ours] The yaw of the last committed step when it turned in place (left positive);
  // none after a translation. policy.no_turn_back ranks the turn undoing it last.
  std::optional<double> last_turn_deg_;
};

}  // namespace valerant
