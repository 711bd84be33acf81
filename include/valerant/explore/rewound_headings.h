#pragma once
// [ours] Headings rewound out of (dead_pocket.ban_rewound_headings; docs/pockets.md). A
// rewind restores the state before the translation that led into a dead pocket and puts
// the cells its steps walked into F. When that walk added no cell to F (it stayed in the
// anchor's cell, or crossed cells F already held), nothing keeps the agent from making
// the same choice from the same state, and it walks into the same pocket again: in the
// visual runs a `lw@16`, three turns and a rewind, over and over until every rewind was
// spent (kaos2 and oa_dm2 spawn 0; oa_dm5 spawn 0 with free_way_back).
//
// This memory keeps, for each state a rewind went back to, the walk of every translation
// that left that state into a pocket (end minus start camera centre, map frame). A
// translation from that state whose walk heads, on the grid's floor, within
// `tolerance_deg` of one of them is barred; Episode uses a quarter of jw / lw's turn
// (11.25 degrees), so of the paper's candidates only the rewound one's own family (its
// prefixes and short versions) is barred, not its neighbours.
//
// A state is named by its committed steps k (the trajectory is the same up to it). A
// rewind to the state after k discards every later state, and their walks with them; a
// commit from k keeps k's walks, since a later rewind can bring the agent back to k.
// Walks shorter than kMinWalk (map units) have no heading and are neither kept nor barred.
#include <Eigen/Core>
#include <map>
#include <vector>

#include "valerant/geometry/coverage_grid.h"

namespace valerant {

class RewoundHeadings {
 public:
  static constexpr double kMinWalk = 1e-6;

  explicit RewoundHeadings(double tolerance_deg) : tolerance_deg_(tolerance_deg) {}

  // A rewind restored the state after `committed_steps` committed steps; `walk` is the
  // displacement of the translation that the rewind discarded first (the one committed
  // from that state).
  void rewoundTo(int committed_steps, const Eigen::Vector3d& walk);
  // Whether a translation with displacement `walk` from the state after
  // `committed_steps` heads where a walk rewound out of went from there, the headings
  // measured on `grid`'s floor.
  bool barred(int committed_steps, const Eigen::Vector3d& walk, const CoverageGrid& grid) const;
  // Walks kept, over every state.
  size_t walks() const;

 private:
  double tolerance_deg_;
  std::map<int, std::vector<Eigen::Vector3d>> walks_;  // by the committed steps of the state they left
};

}  // namespace valerant
