#include "valerant/eval/live_coverage.h"

namespace valerant {

LiveCoverage::LiveCoverage(const quake3::ReachableFloor& reachable) : cells_(reachable) {}

double LiveCoverage::update(const Episode& episode) {
  const auto& keyframes = episode.map().keyframes();
  const bool dropped = counted_ > keyframes.size() || (counted_ > 0 && keyframes[counted_ - 1]->id != last_counted_id_);
  const bool tied = alignment_.aligned || alignment_.floor_aligned;
  if (dropped || !tied || keyframes.size() >= 2 * fitted_at_) {
    alignment_ = alignEpisode(episode);
    observed_.clear();
    counted_ = 0;
    fitted_at_ = keyframes.size();
    ++refits_;
  }
  if (!alignment_.aligned && !alignment_.floor_aligned) return 0;
  const double band = episode.config().collision.height_low;
  for (; counted_ < keyframes.size(); ++counted_) {
    const auto seen = cells_.observedBy(*keyframes[counted_], alignment_.map_to_world_metres, band);
    observed_.insert(seen.begin(), seen.end());
    last_counted_id_ = keyframes[counted_]->id;
  }
  return cells_.count() > 0 ? 100.0 * observed_.size() / cells_.count() : 0.0;
}

}  // namespace valerant
