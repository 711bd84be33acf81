#pragma once
// The ground-truth source of the frames being tracked now, filled from the world's
// rollouts: whoever feeds a SLAM a rollout holds it here while the frames are tracked,
// and the oracle SLAM looks each frame up by its stamp (rollout id, index). Holding ends
// with the Hold, so the source keeps only the rollouts in flight. Made with
// std::make_shared only (a Hold shares the source it holds frames in).
#include <map>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "valerant/slam/ground_truth_source.h"
#include "valerant/world/world_model.h"

namespace valerant {

class RolloutTruth : public GroundTruthSource, public std::enable_shared_from_this<RolloutTruth> {
 public:
  // Keeps the frames it put in the source there until it is destroyed.
  class Hold {
   public:
    Hold(Hold&&) = default;
    Hold& operator=(Hold&&) = delete;  // would drop what the target holds unreleased
    ~Hold();

   private:
    friend class RolloutTruth;
    Hold(std::shared_ptr<RolloutTruth> source, std::vector<FrameStamp> stamps)
        : source_(std::move(source)), stamps_(std::move(stamps)) {}
    std::shared_ptr<RolloutTruth> source_;
    std::vector<FrameStamp> stamps_;
  };

  // Holds the truth of every frame of `rollout` (none when it has no ground truth).
  [[nodiscard]] Hold hold(const Rollout& rollout);
  // Holds the truth of one frame.
  [[nodiscard]] Hold hold(const FrameStamp& stamp, const FrameTruth& truth);

  std::optional<TrueView> viewOf(const FrameStamp& stamp) const override;

 private:
  using Key = std::pair<uint64_t, int>;  // rollout id, frame index
  struct Held {
    TrueView view;
    int holds = 0;  // Holds naming this frame
  };
  void put(const FrameStamp& stamp, const FrameTruth& truth);
  void release(const std::vector<FrameStamp>& stamps);

  mutable std::mutex mutex_;
  std::map<Key, Held> views_;
};

}  // namespace valerant
