#pragma once
// The reachable floor cells near a wall, where valerant_dataset's wall turns start: a
// turn in place a metre or two from a wall is the view the depth prior got most wrong
// (the camera's whole frame is one close, dimly lit surface), and random reachable
// cells rarely stand there.
#include <Eigen/Core>
#include <vector>

namespace valerant::dataset {

struct NearWallParams {
  float cell_size = 16.f;   // the reachable floor's grid (game units)
  float step_height = 18.f; // Quake III's STEPSIZE: a neighbour higher than this is a wall
  int max_cells = 4;        // near: a wall within this many cells along x or y
};

// Indices into `cells` (reachable floor cells at feet level, game units, on a grid of
// params.cell_size) of the cells with a wall within params.max_cells cells along +x, -x,
// +y or -y. A column (a grid xy) is open from a floor at height z if it holds a
// reachable cell no higher than z + step_height (a floor one may walk or drop to); the
// first column along a direction that is not open is the wall.
std::vector<size_t> nearWallCells(const std::vector<Eigen::Vector3f>& cells, const NearWallParams& params = {});

}  // namespace valerant::dataset
