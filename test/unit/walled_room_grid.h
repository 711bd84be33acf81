#pragma once
// A hand-built coverage grid for the whole-level tests: unit cells (cell (64 + x,
// 64 + y) covers the floor point (x, y), u = +X, v = +Y, as in test_policy.cpp), a
// room of observed floor x in [0, 4], y in [-1, 1] walled by obstacle cells (3 points
// each) at y = +-2 (x in [-1, 5]), x = 5 and x = -1 (y in [-1, 1]) except a doorway
// (-1, 0) that is unknown. The agent has stood at (3, 0).
//
//   y= 2   O O O O O O O
//   y= 1   O . . . . . O
//   y= 0   ? F . . A . O      F: the only goal frontier (its west neighbour is unknown)
//   y=-1   O . . . . . O      A: the agent's cell (visited)
//   y=-2   O O O O O O O
//        x=-1 0 1 2 3 4 5
#include "unit_grid.h"

namespace valerant::test {

inline Cell roomCell(int x, int y) { return {64 + x, 64 + y}; }

inline CoverageGrid walledRoomGrid() {
  CoverageGrid g = unitGrid();
  for (int x = 0; x <= 4; ++x)
    for (int y = -1; y <= 1; ++y) g.markObservedFloor({double(x), double(y), 0});
  auto wall = [&](int x, int y) {
    for (int i = 0; i < 3; ++i) g.markObstaclePoint({double(x), double(y), 0.5});
  };
  for (int x = -1; x <= 5; ++x) wall(x, -2), wall(x, 2);
  for (int y = -1; y <= 1; ++y) {
    wall(5, y);
    if (y != 0) wall(-1, y);
  }
  g.markVisited({3, 0, 1});
  return g;
}

}  // namespace valerant::test
