#include "valerant/explore/committed_points.h"

#include <limits>
#include <string>

#include "valerant/common/error.h"

namespace valerant {

CommittedPoints::CommittedPoints(const CollisionConfig& config)
    : steps_kept_(config.previous_steps), min_confidence_(static_cast<float>(config.min_confidence)) {}

void CommittedPoints::add(const std::vector<KeyframeCloud>& keyframes, const std::vector<FloorPlane>& floors) {
  if (keyframes.size() != floors.size())
    throw InputError("committed step", std::to_string(keyframes.size()) + " keyframes but " +
                                           std::to_string(floors.size()) + " keyframe floors");
  if (steps_kept_ <= 0) return;
  auto step = std::make_shared<std::vector<CommittedPoint>>();
  for (size_t k = 0; k < keyframes.size(); ++k) {
    const FloorPlane& floor = floors[k];
    const bool known = floor.known && floor.cameraHeight() > 0;
    for (const CloudPoint& p : keyframes[k].points)
      if (p.confidence >= min_confidence_)
        step->push_back({p.position,
                         known ? static_cast<float>(floor.normalisedHeight(p.position.cast<double>()))
                               : std::numeric_limits<float>::quiet_NaN(),
                         p.confidence});
  }
  steps_.push_back(std::move(step));
  if (static_cast<int>(steps_.size()) > steps_kept_) steps_.erase(steps_.begin(), steps_.end() - steps_kept_);
}

}  // namespace valerant
