#pragma once
// Failed-region memory F (paper eq. 8): grid cells of trajectory segments discarded by
// a dead-pocket rewind. A candidate that enters F is inadmissible. "Enters" means a
// sample cell in F other than the candidate's own start cell: after a rewind the agent
// stands at the anchor, whose neighbourhood the discarded segment usually shares, and
// must still be able to leave it in another direction. A turn in place enters nothing:
// its body stays in the start cell, and the cells its reconstructed camera centres
// pass through are the SLAM's jitter (a 150-step visual run on oa_dm1 ended "stuck"
// at step 36 when both turns read a neighbouring cell of F).
#include <set>

#include "valerant/geometry/coverage_grid.h"

namespace valerant {

class FailedRegionMemory {
 public:
  void add(const std::set<Cell>& cells) { cells_.insert(cells.begin(), cells.end()); }
  bool contains(const Cell& c) const { return cells_.count(c) > 0; }
  bool enters(const std::set<Cell>& candidate_cells, const Cell& start, bool rotation_only = false) const {
    if (rotation_only) return false;
    for (const Cell& c : candidate_cells)
      if (c != start && contains(c)) return true;
    return false;
  }
  // [ours] dead_pocket.cross_failed: only the candidate's end cell counts. The
  // discarded segment's cells are a walked line; a candidate that crosses it does not
  // re-enter the pocket, which lies where that line led, and one that ends on it does.
  bool endsIn(const Cell& end, const Cell& start, bool rotation_only = false) const {
    return !rotation_only && end != start && contains(end);
  }
  // Removes `cells` where held; returns how many were.
  size_t remove(const std::set<Cell>& cells) {
    size_t n = 0;
    for (const Cell& c : cells) n += cells_.erase(c);
    return n;
  }
  const std::set<Cell>& cells() const { return cells_; }
  // [ours] Forgets every cell (dead_pocket.forget_failed_when_trapped); returns how many.
  size_t forget() {
    const size_t n = cells_.size();
    cells_.clear();
    return n;
  }

 private:
  std::set<Cell> cells_;
};

}  // namespace valerant
