#include "valerant/explore/rewind_controller.h"

#include <algorithm>

namespace valerant {

std::vector<uint64_t> RewindController::recordStep(uint64_t checkpoint, const Cell& start_cell, bool committed,
                                                   bool rotation_only, const std::set<Cell>& cells,
                                                   const PocketSignals& signals) {
  const bool walk_in_cell = config_.walk_in_cell_is_turn && signals.ended_in_start_cell;
  const bool translational = committed && !rotation_only && !walk_in_cell;
  stalled_ = translational ? 0 : stalled_ + 1;
  if (config_.stagnant_steps > 0)
    stagnant_ = signals.new_floor_cells >= config_.stagnant_cells ? 0 : stagnant_ + 1;
  // A drop that started in contact is no drop anchor: a rewind there would put the
  // agent back where a graze left it, maybe inside a brush (docs/pockets.md, kaos2).
  const bool drop = translational && signals.drop && !signals.start_in_contact && config_.stagnant_steps > 0;
  steps_.push_back({checkpoint, start_cell, translational, drop, committed ? cells : std::set<Cell>{}});
  std::vector<uint64_t> released;
  if (!translational) released.push_back(checkpoint);
  if (!rewindsLeft()) {  // no rewind can follow: nothing to keep
    releaseAll(released);
    return released;
  }
  if (!translational) return released;
  // Held: the checkpoints_kept most recent anchors and, where one is held, the latest
  // drop anchor with the checkpoints_kept anchors before it, so that a pocket met after
  // a stagnant rewind to the drop can still be rewound out of. The anchors between are
  // released (a checkpoint is tens of MB); their steps stay, for their cells in F.
  std::vector<bool> keep(steps_.size(), false);
  auto holdBefore = [&](size_t end, int n) {
    for (size_t i = end; i-- > 0 && n > 0;)
      if (steps_[i].held) keep[i] = true, --n;
  };
  holdBefore(steps_.size(), config_.checkpoints_kept);
  for (size_t i = steps_.size(); i-- > 0;)
    if (steps_[i].drop && steps_[i].held) {
      keep[i] = true;
      holdBefore(i, config_.checkpoints_kept);
      break;
    }
  size_t keep_from = steps_.size();
  for (size_t i = 0; i < steps_.size(); ++i) {
    if (keep[i]) keep_from = std::min(keep_from, i);
    if (steps_[i].held && !keep[i]) {
      released.push_back(steps_[i].checkpoint);
      steps_[i].held = false;
    }
  }
  steps_.erase(steps_.begin(), steps_.begin() + keep_from);
  return released;
}

void RewindController::releaseAll(std::vector<uint64_t>& released) {
  for (const Step& s : steps_)
    if (s.held) released.push_back(s.checkpoint);
  steps_.clear();
}

bool RewindController::pocketDeclared() const {
  return stalled_ >= config_.rotation_only_steps || (config_.stagnant_steps > 0 && stagnant_ >= config_.stagnant_steps);
}

std::optional<RewindDecision> RewindController::check(const std::function<bool(const Cell&)>& in_failed) {
  if (!rewindsLeft() || !pocketDeclared()) return std::nullopt;
  const bool rotations = stalled_ >= config_.rotation_only_steps;
  // The most recent anchor: the last translational step, whose checkpoint is always held.
  auto anchor = std::find_if(steps_.rbegin(), steps_.rend(), [](const Step& s) { return s.held; });
  if (anchor == steps_.rend()) return std::nullopt;
  if (!rotations) {  // a stagnant pocket: back over the latest drop, where one is held
    const auto drop = std::find_if(steps_.rbegin(), steps_.rend(), [](const Step& s) { return s.held && s.drop; });
    if (drop != steps_.rend()) anchor = drop;
  }
  RewindDecision d = rewindTo(anchor.base() - 1);
  if (config_.reach_past_known_pocket && in_failed) {
    const auto teaches_nothing = [&](const RewindDecision& r) {
      return std::all_of(r.failed_cells.begin(), r.failed_cells.end(), in_failed);
    };
    int passed = 0;
    while (teaches_nothing(d)) {
      anchor = std::find_if(std::next(anchor), steps_.rend(), [](const Step& s) { return s.held; });
      if (anchor == steps_.rend()) break;  // none further back: the paper's rewind
      d = rewindTo(anchor.base() - 1);
      d.reached_past = ++passed;
    }
  }
  d.stagnant = !rotations;
  return d;
}

RewindDecision RewindController::rewindTo(std::deque<Step>::const_iterator anchor) const {
  RewindDecision d;
  d.checkpoint = anchor->checkpoint;
  for (auto it = anchor; it != steps_.end(); ++it) {
    d.failed_cells.insert(it->cells.begin(), it->cells.end());
    ++d.discarded_steps;
  }
  // The cells around the anchor stay free: every candidate leaves the anchor through
  // them, so marking them would close the routes the rewind is for.
  const int r = config_.anchor_free_cells;
  for (int dx = -r; dx <= r; ++dx)
    for (int dy = -r; dy <= r; ++dy) d.failed_cells.erase({anchor->start_cell.first + dx, anchor->start_cell.second + dy});
  return d;
}

std::vector<uint64_t> RewindController::apply(const RewindDecision& decision) {
  std::vector<uint64_t> released;
  auto first = std::find_if(steps_.begin(), steps_.end(),
                            [&](const Step& s) { return s.held && s.checkpoint == decision.checkpoint; });
  // The anchor's own checkpoint is consumed too: the next rewind reaches further back.
  for (auto it = first; it != steps_.end(); ++it)
    if (it->held) released.push_back(it->checkpoint);
  steps_.erase(first, steps_.end());
  stalled_ = 0;
  stagnant_ = 0;
  ++rewinds_;
  if (!rewindsLeft()) releaseAll(released);
  return released;
}

bool RewindController::canRewindLater() const {
  return rewindsLeft() && std::any_of(steps_.begin(), steps_.end(), [](const Step& s) { return s.held; });
}

std::vector<uint64_t> RewindController::retained() const {
  std::vector<uint64_t> ids;
  for (const auto& s : steps_)
    if (s.held) ids.push_back(s.checkpoint);
  return ids;
}

}  // namespace valerant
