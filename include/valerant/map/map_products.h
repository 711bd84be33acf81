#pragma once
// The map's derived products, each built keyframe by keyframe so that a live map can
// extend them by the newest keyframes instead of starting over (live_map.h), while
// MapFusion builds them from all keyframes in one pass with the same code.
//   VoxelCloudBuilder  voxel-averaged cloud: position, colour, confidence and height
//                      averaged per cube of the voxel size, any extent
//   insertKeyframe     OctoMap occupancy by ray casting from the keyframe's camera centre
//   updateInnerNodes   inner nodes brought up to date after insertions (empty trees too)
//   FloorGridBuilder   2D floor/obstacle grid on the exploration grid's floor plane
#include <Eigen/Core>
#include <unordered_map>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/geometry/coverage_grid.h"
#include "valerant/map/map_fusion.h"

namespace octomap {
class ColorOcTree;
}

namespace valerant {

class VoxelCloudBuilder {
 public:
  explicit VoxelCloudBuilder(double voxel_size);
  void add(const FusedKeyframe& keyframe);
  // Voxels sorted by (z, y, x) key, so the output does not depend on insertion order.
  std::vector<FusedPoint> cloud() const;

 private:
  using Key = Eigen::Matrix<int64_t, 3, 1>;
  struct KeyHash {
    size_t operator()(const Key& k) const;
  };
  struct Voxel {
    Key key;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    Eigen::Vector4d colour_confidence = Eigen::Vector4d::Zero();
    double h = 0;
    int count = 0;
  };
  float inverse_leaf_;
  std::unordered_map<Key, size_t, KeyHash> index_;
  std::vector<Voxel> voxels_;
};

// Rays from the keyframe's camera centre to each of its points, up to `max_range`,
// then the points' colours averaged into their leaves. Only leaves are updated (nothing
// is pruned): call updateInnerNodes after the last keyframe of a batch.
void insertKeyframe(octomap::ColorOcTree& tree, const FusedKeyframe& keyframe, double max_range);

// Propagates occupancy and colour to the inner nodes. Safe on an empty tree, which
// ColorOcTree::updateInnerOccupancy is not (OctoMap 1.9 dereferences the null root:
// map_fusion died on the empty keyframe clouds of its first update at 160 x 120).
void updateInnerNodes(octomap::ColorOcTree& tree);

// Floor (|h| < eta_low) and body-level obstacles (eta_low <= h <= eta_high) on the
// floor plane of `grid`'s anchor, over the same extent; obstacles win over floor.
class FloorGridBuilder {
 public:
  FloorGridBuilder(const CoverageGrid& grid, double resolution, const CollisionConfig& heights);
  void add(const FusedKeyframe& keyframe);
  const FloorGrid& grid() const { return floor_; }

 private:
  CoverageGrid grid_;
  double height_low_, height_high_;
  FloorGrid floor_;
};

}  // namespace valerant
