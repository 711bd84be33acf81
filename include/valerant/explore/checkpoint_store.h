#pragma once
// States saved under the synchronised checkpoint ids of the world model (the first
// thing each exploration step does), so the world, every SLAM branch and the floor estimator always
// return to the same moment. Unknown, dropped or reused ids are InputErrors that name
// the id: a caller with a stale id gets a clear error, never a silent wrong state.
#include <map>
#include <string>

#include "valerant/common/error.h"
#include "valerant/world/world_model.h"

namespace valerant {

template <class State>
class CheckpointStore {
 public:
  void save(CheckpointId id, State state) {
    if (!saved_.emplace(id, std::move(state)).second)
      throw InputError("checkpoint " + std::to_string(id), "already taken (ids are never reused)");
  }
  const State& at(CheckpointId id) const {
    const auto it = saved_.find(id);
    if (it == saved_.end()) throw InputError("checkpoint " + std::to_string(id), "unknown or already dropped");
    return it->second;
  }
  bool contains(CheckpointId id) const { return saved_.count(id) > 0; }
  void drop(CheckpointId id) { saved_.erase(id); }
  void clear() { saved_.clear(); }

 private:
  std::map<CheckpointId, State> saved_;
};

}  // namespace valerant
