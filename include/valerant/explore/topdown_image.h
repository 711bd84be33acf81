#pragma once
// The map seen from above on the anchor floor plane: floor points in their colour,
// body-level obstacles dark red, failed cells shaded red, every step's candidate
// branches (green admissible, red collision, orange entering F or heading into a pocket
// rewound from, grey lost), the committed trajectory in yellow and the start in blue.
// Cropped to what is drawn.
#include <opencv2/core.hpp>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/explore/episode.h"
#include "valerant/explore/failed_region_memory.h"
#include "valerant/geometry/coverage_grid.h"
#include "valerant/map/map_fusion.h"

namespace valerant {

// RGB image, `pixels_per_cell` pixels per coverage-grid cell.
cv::Mat drawTopdown(const std::vector<FusedPoint>& points, const CoverageGrid& grid,
                    const std::vector<Eigen::Isometry3d>& trajectory, const std::vector<StepRecord>& history,
                    const FailedRegionMemory& failed, const CollisionConfig& bands, int pixels_per_cell);

}  // namespace valerant
