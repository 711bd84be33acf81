#include "valerant/explore/rewound_headings.h"

#include <cmath>

#include "valerant/geometry/open_direction.h"

namespace valerant {

void RewoundHeadings::rewoundTo(int committed_steps, const Eigen::Vector3d& walk) {
  walks_.erase(walks_.upper_bound(committed_steps), walks_.end());  // states the rewind discarded
  if (walk.norm() >= kMinWalk) walks_[committed_steps].push_back(walk);
}

bool RewoundHeadings::barred(int committed_steps, const Eigen::Vector3d& walk, const CoverageGrid& grid) const {
  const auto state = walks_.find(committed_steps);
  if (state == walks_.end() || walk.norm() < kMinWalk) return false;
  const double heading = floorAngle(grid, walk);
  for (const Eigen::Vector3d& rewound : state->second)
    if (std::abs(turnDeg(floorAngle(grid, rewound), heading)) < tolerance_deg_) return true;
  return false;
}

size_t RewoundHeadings::walks() const {
  size_t n = 0;
  for (const auto& [state, walks] : walks_) n += walks.size();
  return n;
}

}  // namespace valerant
