#pragma once
// The global map: keyframe clouds of committed branches, each point with its
// floor-normalised height. Fusion only appends keyframes; a rewind truncates back to a
// marker. The derived products (voxel-averaged cloud, OctoMap occupancy by ray
// insertion from the keyframe origins, 2D floor/obstacle grid; map_products.h) are
// rebuilt from the kept keyframes when asked for, so a rewind never leaves stale
// geometry behind. live_map.h keeps them current instead, for a node that publishes
// them after every step.
#include <Eigen/Geometry>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/geometry/coverage_grid.h"
#include "valerant/geometry/floor_plane.h"
#include "valerant/slam/slam.h"

namespace octomap {
class ColorOcTree;
}

namespace valerant {

struct FusedPoint {
  Eigen::Vector3f position;
  std::array<uint8_t, 3> rgb{};
  float confidence = 0;
  float h = 0;  // normalised height over its keyframe's floor
};

struct FusedKeyframe {
  uint64_t id = 0;  // newKeyframeId(): how a mirror of the map (live_map.h) tells keyframes apart
  Eigen::Isometry3d camera_to_map;
  std::vector<FusedPoint> points;
};

// A 2D occupancy grid on the anchor floor plane, ROS map_server values: 0 free,
// 100 occupied, -1 unknown. Row 0 is the lowest v (map_server's image is flipped).
struct FloorGrid {
  int width = 0, height = 0;
  double resolution = 0;               // map units per cell
  Eigen::Vector2d origin;              // (u, v) of cell (0, 0)'s corner on the anchor floor
  std::vector<int8_t> cells;           // row-major, width * height
};

// A keyframe id not given out before, in this process or (with overwhelming
// probability) in any other.
uint64_t newKeyframeId();

class MapFusion {
 public:
  MapFusion(const MapConfig& map_config, const CollisionConfig& collision_config);

  // Keeps points with confidence >= min_confidence; `floor` is the keyframe's floor.
  void fuse(const KeyframeCloud& cloud, const FloorPlane& floor);
  // Appends a keyframe fused elsewhere (a mirror of another process's map), id and all.
  void add(std::shared_ptr<const FusedKeyframe> keyframe) { keyframes_.push_back(std::move(keyframe)); }
  size_t marker() const { return keyframes_.size(); }
  void truncate(size_t marker);
  const std::vector<std::shared_ptr<const FusedKeyframe>>& keyframes() const { return keyframes_; }
  size_t pointCount() const;

  // Voxel-averaged cloud (cubes of voxel_size, any extent); position, colour, confidence and
  // height averaged per voxel; sorted by voxel.
  std::vector<FusedPoint> voxelCloud(double voxel_size) const;
  // Occupancy by ray casting from each keyframe's camera centre (OctoMap).
  std::unique_ptr<octomap::ColorOcTree> octree(double resolution) const;
  // Floor (|h| < eta_low) and body-level obstacles (eta_low <= h <= eta_high) on the
  // floor plane of `grid`'s anchor, over the same extent; obstacles win over floor.
  FloorGrid floorGrid(const CoverageGrid& grid, double resolution) const;

 private:
  MapConfig map_config_;
  CollisionConfig collision_config_;
  std::vector<std::shared_ptr<const FusedKeyframe>> keyframes_;
};

}  // namespace valerant
