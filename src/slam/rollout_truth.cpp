#include "valerant/slam/rollout_truth.h"

namespace valerant {

RolloutTruth::Hold::~Hold() {
  if (source_) source_->release(stamps_);
}

RolloutTruth::Hold RolloutTruth::hold(const Rollout& rollout) {
  std::vector<FrameStamp> stamps;
  for (size_t i = 0; i < rollout.truth.size(); ++i) {
    stamps.push_back({rollout.id, static_cast<int>(i)});
    put(stamps.back(), rollout.truth[i]);
  }
  return Hold(shared_from_this(), std::move(stamps));
}

RolloutTruth::Hold RolloutTruth::hold(const FrameStamp& stamp, const FrameTruth& truth) {
  put(stamp, truth);
  return Hold(shared_from_this(), {stamp});
}

std::optional<TrueView> RolloutTruth::viewOf(const FrameStamp& stamp) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = views_.find({stamp.rollout, stamp.index});
  if (it == views_.end()) return std::nullopt;
  return it->second.view;
}

void RolloutTruth::put(const FrameStamp& stamp, const FrameTruth& truth) {
  std::lock_guard<std::mutex> lock(mutex_);
  // The depth image is shared, not copied: a rollout's truth is immutable once made, so
  // a frame held twice (the committed SLAM and a branch fed the same frame) keeps one view.
  Held& held = views_[{stamp.rollout, stamp.index}];
  if (held.holds++ == 0) held.view = TrueView{truth.camera_to_world, truth.depth_m};
}

void RolloutTruth::release(const std::vector<FrameStamp>& stamps) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& stamp : stamps) {
    const auto it = views_.find({stamp.rollout, stamp.index});
    if (it != views_.end() && --it->second.holds == 0) views_.erase(it);
  }
}

}  // namespace valerant
