#pragma once
// Dead-pocket rewind (paper section 3.3.3, eq. 8, appendix A). A dead pocket is
// declared after `rotation_only_steps` (3) consecutive steps that commit a rotation
// only or stall. The agent then returns to the checkpoint taken just before its most
// recent translational commit, the state before it walked into the pocket, and every
// cell the discarded steps passed through goes into the failed-region memory F, except
// the anchor's own cell and, with `anchor_free_cells` ([ours], a Chebyshev radius, default
// 0 as the paper) above 0, its neighbours: every route out of the anchor starts there.
//
// Rewind anchors: the checkpoints taken before translational commits; the
// `checkpoints_kept` (3) most recent are retained, older ones released. A checkpoint
// before a rotation-only step or a stall is no anchor (rewinding to it would leave the
// agent in the very pocket it is escaping), so it is released as soon as its step is
// recorded; once no rewind can follow (disabled, or `max_rewinds` spent) every
// checkpoint is. A checkpoint holds a copy of the SLAM, floor and grid state, so one
// kept per step of a long turn in place grew memory by tens of MB a step. Each rewind
// consumes its anchor, so a second dead pocket reaches further back. At most
// `max_rewinds` (2) per episode.
//
// [ours] Stagnant pockets (docs/pockets.md; off by default, the paper). In a long
// episode the agent can circle in a part it has seen, a translation and a half turn in
// turn, which never makes three rotations in a row; and where it walked off a ledge, the
// three most recent anchors all lie below it. With `stagnant_steps` K > 0, K steps in a
// row (stalls included) that each observed fewer than `stagnant_cells` new floor cells
// also declare a dead pocket. Its rewind goes to the drop anchor, the checkpoint before
// the latest committed translation that ended `drop_height` eye heights or more below
// its start (a drop: the agent cannot walk back up) from a start not in contact (fewer
// than N_occ committed points inside the body there: a drop that starts where a graze
// left the camera would rewind it into the brush), where one is held; else to the most
// recent anchor, as the paper's. The drop anchor is held beyond the `checkpoints_kept`
// most recent ones, with the `checkpoints_kept` anchors before it, so that a pocket met
// after the rewind can still be left; the anchors between are released (a checkpoint is
// tens of MB), though their steps' cells are kept for F: at most 2 checkpoints_kept + 1
// checkpoints are held. Every cell the discarded steps passed through goes into F, the
// drop's own path too, so the agent does not walk off the same ledge again.
//
// [ours] Trapped: a dead pocket is declared that no rewind can follow (no rewind left, or
// rewinds left but no anchor held: each rewind consumes its anchor, and in a pocket met
// again and again they all go). In the 150-step runs most episodes ended so, turning in
// place for tens of steps with every translation colliding or entering F
// (docs/pockets.md); with dead_pocket.forget_failed_when_trapped the Episode then forgets F.
//
// [ours] Known pockets (dead_pocket.reach_past_known_pocket): a rewind whose discarded
// steps would add no cell to F teaches the agent nothing; from the restored state the
// same choices walk into the same pocket (a short walk that never left the anchor's
// cell, then three turns, rewound again and again until no rewind is left). Such a
// rewind goes to the held anchor before instead, and on, until one adds a cell or none
// is held.
//
// [ours] Walks in a cell (dead_pocket.walk_in_cell_is_turn): a committed translation that
// ends in the grid cell it started in counts as a turn, so it neither resets the count
// of rotation-only steps nor becomes an anchor. Otherwise a short walk that moved less
// than a cell, then three turns, rewinds to the walk's own start, from which the same
// walk is chosen again (docs/pockets.md, the replay loop).
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <set>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/geometry/coverage_grid.h"

namespace valerant {

struct RewindDecision {
  uint64_t checkpoint = 0;           // where to go back to
  int discarded_steps = 0;           // committed steps undone
  std::set<Cell> failed_cells;       // cells to add to F (the anchor's neighbourhood excluded)
  bool stagnant = false;             // [ours] declared by the stagnant-pocket rule, not by rotations
  int reached_past = 0;              // [ours] anchors passed over as known pockets (reach_past_known_pocket)
};

// [ours] What a step did for the stagnant-pocket rule (see above).
struct PocketSignals {
  bool drop = false;        // a committed translation that ended drop_height or more below its start
  int new_floor_cells = 0;  // floor cells of the coverage grid the step observed first
  bool start_in_contact = false;  // N_occ or more committed points inside the body at the step's start
  bool ended_in_start_cell = false;  // a committed translation whose last camera centre lies in its start cell
};

class RewindController {
 public:
  explicit RewindController(const DeadPocketConfig& config) : config_(config) {}

  // One exploration step that started from `checkpoint` (whose camera stood in
  // `start_cell`): either a commit (translational or rotation-only) passing through
  // `cells`, or a stall. Returns the checkpoints that are no longer needed (this
  // step's own, unless it is an anchor).
  std::vector<uint64_t> recordStep(uint64_t checkpoint, const Cell& start_cell, bool committed,
                                   bool rotation_only, const std::set<Cell>& cells, const PocketSignals& signals = {});
  // A rewind when a dead pocket is declared and one is allowed and possible;
  // `in_failed` tells which cells F holds (for reach_past_known_pocket; none: the paper).
  std::optional<RewindDecision> check(const std::function<bool(const Cell&)>& in_failed = {});
  // Applies `decision` (after the caller restored its checkpoint); returns checkpoints
  // that are no longer needed.
  std::vector<uint64_t> apply(const RewindDecision& decision);

  // Whether a dead pocket could still be rewound out of: enabled, rewinds left and an
  // anchor retained. A stall without that changes nothing, so nothing can follow it.
  bool canRewindLater() const;
  // A dead pocket is declared (by either rule) that no rewind can follow.
  bool trapped() const { return pocketDeclared() && !canRewindLater(); }
  int rewinds() const { return rewinds_; }
  int stalledSteps() const { return stalled_; }
  int stagnantSteps() const { return stagnant_; }
  // Every checkpoint the controller may still rewind to.
  std::vector<uint64_t> retained() const;

 private:
  struct Step {
    uint64_t checkpoint;
    Cell start_cell;
    bool held;           // an anchor whose checkpoint is still held: a translation's, unless it lies between the
                         // drop anchor and the recent ones
    bool drop;           // [ours] a translation that dropped
    std::set<Cell> cells;
  };
  // The rewind to the step at `anchor` (held): every step from it on is discarded.
  RewindDecision rewindTo(std::deque<Step>::const_iterator anchor) const;
  bool rewindsLeft() const { return config_.enabled && rewinds_ < config_.max_rewinds; }
  bool pocketDeclared() const;
  // No rewind can follow: releases every anchor and forgets the steps.
  void releaseAll(std::vector<uint64_t>& released);
  DeadPocketConfig config_;
  std::deque<Step> steps_;  // since the oldest retained anchor
  int stalled_ = 0;         // consecutive rotation-only or stalled steps
  int stagnant_ = 0;        // [ours] consecutive steps that observed under stagnant_cells new floor cells
  int rewinds_ = 0;
};

}  // namespace valerant
