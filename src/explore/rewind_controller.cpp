#include "valerant/explore/rewind_controller.h"

#include <algorithm>

namespace valerant {

std::vector<uint64_t> RewindController::recordStep(uint64_t checkpoint, const Cell& start_cell, bool committed,
                                                   bool rotation_only, const std::set<Cell>& cells) {
  const bool translational = committed && !rotation_only;
  stalled_ = translational ? 0 : stalled_ + 1;
  steps_.push_back({checkpoint, start_cell, translational, committed ? cells : std::set<Cell>{}});
  std::vector<uint64_t> released;
  if (!translational) released.push_back(checkpoint);
  if (!rewindsLeft()) {  // no rewind can follow: nothing to keep
    releaseAll(released);
    return released;
  }
  if (!translational) return released;
  // Keep the steps from the oldest retained anchor on; release what lies before it.
  int anchors = 0;
  size_t keep_from = steps_.size();
  for (size_t i = steps_.size(); i-- > 0;) {
    if (steps_[i].translational && ++anchors > config_.checkpoints_kept) break;
    keep_from = i;
  }
  for (size_t i = 0; i < keep_from; ++i)
    if (steps_[i].translational) released.push_back(steps_[i].checkpoint);
  steps_.erase(steps_.begin(), steps_.begin() + keep_from);
  return released;
}

void RewindController::releaseAll(std::vector<uint64_t>& released) {
  for (const Step& s : steps_)
    if (s.translational) released.push_back(s.checkpoint);
  steps_.clear();
}

std::optional<RewindDecision> RewindController::check() {
  if (!rewindsLeft() || stalled_ < config_.rotation_only_steps) return std::nullopt;
  // The most recent anchor: the last translational step.
  auto anchor = std::find_if(steps_.rbegin(), steps_.rend(), [](const Step& s) { return s.translational; });
  if (anchor == steps_.rend()) return std::nullopt;
  RewindDecision d;
  const auto first = anchor.base() - 1;  // forward iterator to the anchor step
  d.checkpoint = first->checkpoint;
  for (auto it = first; it != steps_.end(); ++it) {
    d.failed_cells.insert(it->cells.begin(), it->cells.end());
    ++d.discarded_steps;
  }
  // The cells around the anchor stay free: every candidate leaves the anchor through
  // them, so marking them would close the routes the rewind is for.
  const int r = config_.anchor_free_cells;
  for (int dx = -r; dx <= r; ++dx)
    for (int dy = -r; dy <= r; ++dy) d.failed_cells.erase({first->start_cell.first + dx, first->start_cell.second + dy});
  return d;
}

std::vector<uint64_t> RewindController::apply(const RewindDecision& decision) {
  std::vector<uint64_t> released;
  auto first = std::find_if(steps_.begin(), steps_.end(),
                            [&](const Step& s) { return s.checkpoint == decision.checkpoint; });
  // The anchor's own checkpoint is consumed too: the next rewind reaches further back.
  for (auto it = first; it != steps_.end(); ++it)
    if (it->translational) released.push_back(it->checkpoint);
  steps_.erase(first, steps_.end());
  stalled_ = 0;
  ++rewinds_;
  if (!rewindsLeft()) releaseAll(released);
  return released;
}

bool RewindController::canRewindLater() const {
  return rewindsLeft() && std::any_of(steps_.begin(), steps_.end(), [](const Step& s) { return s.translational; });
}

std::vector<uint64_t> RewindController::retained() const {
  std::vector<uint64_t> ids;
  for (const auto& s : steps_)
    if (s.translational) ids.push_back(s.checkpoint);
  return ids;
}

}  // namespace valerant
