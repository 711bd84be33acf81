#include "valerant/explore/committed_points.h"

namespace valerant {

CommittedPoints::CommittedPoints(const CollisionConfig& config)
    : steps_kept_(config.previous_steps), min_confidence_(static_cast<float>(config.min_confidence)) {}

void CommittedPoints::add(const std::vector<KeyframeCloud>& keyframes) {
  if (steps_kept_ <= 0) return;
  auto step = std::make_shared<std::vector<CloudPoint>>();
  for (const KeyframeCloud& kf : keyframes)
    for (const CloudPoint& p : kf.points)
      if (p.confidence >= min_confidence_) step->push_back(p);
  steps_.push_back(std::move(step));
  if (static_cast<int>(steps_.size()) > steps_kept_) steps_.erase(steps_.begin(), steps_.end() - steps_kept_);
}

}  // namespace valerant
