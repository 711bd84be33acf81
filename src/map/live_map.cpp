#include "valerant/map/live_map.h"

#include <octomap/ColorOcTree.h>

namespace valerant {

LiveMap::LiveMap(const MapConfig& map, const CollisionConfig& collision, const CoverageGrid& grid, double kappa)
    : map_config_(map),
      collision_config_(collision),
      grid_(grid),
      kappa_(kappa),
      voxels_(map.voxel_eye_heights * kappa),
      octree_(std::make_unique<octomap::ColorOcTree>(map.octree_eye_heights * kappa)),
      floor_(grid, map.grid_cell_fraction * grid.cellSize(), collision) {}

LiveMap::~LiveMap() = default;
LiveMap& LiveMap::operator=(LiveMap&&) = default;

size_t LiveMap::update(const std::vector<std::shared_ptr<const FusedKeyframe>>& keyframes) {
  size_t kept = 0;
  while (kept < keyframes_.size() && kept < keyframes.size() && keyframes_[kept]->id == keyframes[kept]->id) ++kept;
  if (kept < keyframes_.size()) {
    *this = LiveMap(map_config_, collision_config_, grid_, kappa_);  // empty again
    kept = 0;
  }
  const double max_range = map_config_.max_range_eye_heights * kappa_;
  for (size_t i = kept; i < keyframes.size(); ++i) {
    voxels_.add(*keyframes[i]);
    insertKeyframe(*octree_, *keyframes[i], max_range);
    floor_.add(*keyframes[i]);
    keyframes_.push_back(keyframes[i]);
  }
  updateInnerNodes(*octree_);  // as MapFusion::octree, so inner nodes' colours agree too
  return keyframes.size() - kept;
}

}  // namespace valerant
