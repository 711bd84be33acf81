#include "valerant/explore/committed_points.h"

#include <limits>
#include <string>

#include "valerant/common/error.h"

namespace valerant {

namespace {
// The rebuilt views keep every second pixel a side: the visual depth is swept at half
// resolution, so each of its values has a pixel of its own (as BranchCheck's views).
constexpr int kViewShrink = 2;

// `frame` at 1 / kViewShrink of its resolution: a frame pixel u lands on u / kViewShrink.
CameraIntrinsics viewOf(const CameraIntrinsics& frame) {
  CameraIntrinsics v = frame;
  v.width /= kViewShrink;
  v.height /= kViewShrink;
  v.fx /= kViewShrink;
  v.fy /= kViewShrink;
  v.cx /= kViewShrink;
  v.cy /= kViewShrink;
  return v;
}
}  // namespace

CommittedPoints::CommittedPoints(const CollisionConfig& config, const CameraIntrinsics& frame)
    : config_(config), view_(viewOf(frame)) {
  if (config_.carve_committed_views > 0 && (view_.width <= 0 || view_.height <= 0 || !(view_.fx > 0)))
    throw InputError("collision.carve_committed_views",
                     "carving the committed points needs the frames' intrinsics, and none were given");
}

std::shared_ptr<const std::vector<CommittedPoint>> CommittedPoints::carve(Carving& carving,
                                                                          const std::vector<DepthView>& views) const {
  auto evidence = std::make_shared<std::vector<FreeSpaceEvidence>>(*carving.evidence);
  auto kept = std::make_shared<std::vector<CommittedPoint>>();
  const std::vector<CommittedPoint>& all = *carving.all;
  for (size_t i = 0; i < all.size(); ++i) {
    const FreeSpaceEvidence e = freeSpaceEvidence(all[i].position.cast<double>(), views, view_,
                                                  config_.see_through_tolerance);
    FreeSpaceEvidence& sum = (*evidence)[i];
    sum.through += e.through;
    sum.support += e.support;
    if (!sum.seenThrough(config_.carve_committed_views)) kept->push_back(all[i]);
  }
  carving.evidence = std::move(evidence);
  return kept;
}

void CommittedPoints::add(const std::vector<KeyframeCloud>& keyframes, const std::vector<FloorPlane>& floors) {
  if (keyframes.size() != floors.size())
    throw InputError("committed step", std::to_string(keyframes.size()) + " keyframes but " +
                                           std::to_string(floors.size()) + " keyframe floors");
  const int steps_kept = config_.previous_steps;
  if (steps_kept <= 0) return;
  const float min_confidence = static_cast<float>(config_.min_confidence);
  auto step = std::make_shared<std::vector<CommittedPoint>>();
  for (size_t k = 0; k < keyframes.size(); ++k) {
    const FloorPlane& floor = floors[k];
    const bool known = floor.known && floor.cameraHeight() > 0;
    for (const CloudPoint& p : keyframes[k].points)
      if (p.confidence >= min_confidence)
        step->push_back({p.position,
                         known ? static_cast<float>(floor.normalisedHeight(p.position.cast<double>()))
                               : std::numeric_limits<float>::quiet_NaN(),
                         p.confidence});
  }
  if (config_.carve_committed_views > 0) {
    auto views = std::make_shared<std::vector<DepthView>>();
    for (const KeyframeCloud& keyframe : keyframes)
      views->push_back(depthViewOfCloud(keyframe, view_, config_.min_confidence));
    // The kept steps' points gather the new views' evidence; the new step's, every kept view's.
    for (size_t s = 0; s < steps_.size(); ++s) steps_[s] = carve(carving_[s], *views);
    Carving fresh{step, std::make_shared<std::vector<FreeSpaceEvidence>>(step->size()), views};
    std::vector<DepthView> every;
    for (const Carving& c : carving_) every.insert(every.end(), c.views->begin(), c.views->end());
    every.insert(every.end(), views->begin(), views->end());
    steps_.push_back(carve(fresh, every));
    carving_.push_back(std::move(fresh));
  } else {
    steps_.push_back(std::move(step));
  }
  if (static_cast<int>(steps_.size()) > steps_kept) steps_.erase(steps_.begin(), steps_.end() - steps_kept);
  if (static_cast<int>(carving_.size()) > steps_kept) carving_.erase(carving_.begin(), carving_.end() - steps_kept);
}

size_t CommittedPoints::carvedPoints() const {
  size_t carved = 0;
  for (size_t s = 0; s < carving_.size(); ++s) carved += carving_[s].all->size() - steps_[s]->size();
  return carved;
}

}  // namespace valerant
