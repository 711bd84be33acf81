#pragma once
// Failed-region memory F (paper eq. 8): grid cells of trajectory segments discarded by
// a dead-pocket rewind. A candidate that enters F is inadmissible. "Enters" means a
// sample cell in F other than the candidate's own start cell: after a rewind the agent
// stands at the anchor, whose neighbourhood the discarded segment usually shares, and
// must still be able to leave it in another direction.
#include <set>

#include "valerant/geometry/coverage_grid.h"

namespace valerant {

class FailedRegionMemory {
 public:
  void add(const std::set<Cell>& cells) { cells_.insert(cells.begin(), cells.end()); }
  bool contains(const Cell& c) const { return cells_.count(c) > 0; }
  bool enters(const std::set<Cell>& candidate_cells, const Cell& start) const {
    for (const Cell& c : candidate_cells)
      if (c != start && contains(c)) return true;
    return false;
  }
  const std::set<Cell>& cells() const { return cells_; }

 private:
  std::set<Cell> cells_;
};

}  // namespace valerant
