#pragma once
// A mirror of an episode's map whose products (map_products.h) are kept current as the
// episode goes, for map_fusion, which publishes them after every step. Appended
// keyframes cost only their own points; rebuilding after every step instead made the
// node's work grow with the square of the step count (OctoMap ray insertion is most of
// it: valerant_bench map). A rewind that drops mirrored keyframes rebuilds from the
// kept ones, so no dropped geometry stays behind. The products equal MapFusion's.
#include <memory>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/geometry/coverage_grid.h"
#include "valerant/map/map_fusion.h"
#include "valerant/map/map_products.h"

namespace valerant {

class LiveMap {
 public:
  // `grid`: the episode's exploration grid; `kappa`: its anchor's camera-to-floor
  // distance, the unit of the voxel, OctoMap and range sizes in `map`.
  LiveMap(const MapConfig& map, const CollisionConfig& collision, const CoverageGrid& grid, double kappa);
  ~LiveMap();
  LiveMap& operator=(LiveMap&&);

  // Makes the mirror hold `keyframes` (the episode's, in order): appends those after
  // the longest prefix with the same ids, or rebuilds when a mirrored keyframe is no
  // longer there. Returns the number of keyframes whose points were inserted.
  size_t update(const std::vector<std::shared_ptr<const FusedKeyframe>>& keyframes);

  const std::vector<std::shared_ptr<const FusedKeyframe>>& keyframes() const { return keyframes_; }
  std::vector<FusedPoint> voxelCloud() const { return voxels_.cloud(); }
  const octomap::ColorOcTree& octree() const { return *octree_; }
  const FloorGrid& floorGrid() const { return floor_.grid(); }

 private:
  MapConfig map_config_;
  CollisionConfig collision_config_;
  CoverageGrid grid_;
  double kappa_;
  std::vector<std::shared_ptr<const FusedKeyframe>> keyframes_;
  VoxelCloudBuilder voxels_;
  std::unique_ptr<octomap::ColorOcTree> octree_;
  FloorGridBuilder floor_;
};

}  // namespace valerant
