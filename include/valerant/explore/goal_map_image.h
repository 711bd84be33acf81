#pragma once
// What the whole-level goal sees (frontier_distance.h), cell by cell, oriented as the
// top-down image (the start heading up): unknown cells dark, obstacles dark red, walkable
// cells grey where no goal frontier can be reached from them and green where one can
// (`goal`: the episode's, Episode::goalFrom the agent's cell), visited cells lighter, F red, goal frontiers cyan,
// the agent white. It shows why a step's goal term is 0: no frontier left, or the
// frontiers in a part of the grid the agent's part does not connect to (docs/pockets.md).
#include <opencv2/core.hpp>

#include "valerant/explore/failed_region_memory.h"
#include "valerant/geometry/coverage_grid.h"
#include "valerant/geometry/frontier_distance.h"

namespace valerant {

// RGB image, `pixels_per_cell` pixels per coverage-grid cell, cropped to the known cells.
cv::Mat drawGoalMap(const CoverageGrid& grid, const FrontierDistance& goal, const FailedRegionMemory& failed,
                    const Cell& agent, int pixels_per_cell);

}  // namespace valerant
