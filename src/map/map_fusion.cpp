#include "valerant/map/map_fusion.h"

#include <octomap/ColorOcTree.h>

#include <atomic>
#include <cmath>
#include <random>

#include "valerant/map/map_products.h"

namespace valerant {

MapFusion::MapFusion(const MapConfig& map_config, const CollisionConfig& collision_config)
    : map_config_(map_config), collision_config_(collision_config) {}

void MapFusion::fuse(const KeyframeCloud& cloud, const FloorPlane& floor) {
  auto kf = std::make_shared<FusedKeyframe>();
  kf->id = newKeyframeId();
  kf->camera_to_map = cloud.camera_to_map;
  for (const auto& p : cloud.points) {
    if (p.confidence < map_config_.min_confidence || !p.position.allFinite()) continue;
    const float h = static_cast<float>(floor.normalisedHeight(p.position.cast<double>()));
    if (!std::isfinite(h)) continue;
    kf->points.push_back({p.position, p.rgb, p.confidence, h});
  }
  keyframes_.push_back(std::move(kf));
}

void MapFusion::truncate(size_t marker) {
  if (marker < keyframes_.size()) keyframes_.resize(marker);
}

size_t MapFusion::pointCount() const {
  size_t n = 0;
  for (const auto& kf : keyframes_) n += kf->points.size();
  return n;
}

std::vector<FusedPoint> MapFusion::voxelCloud(double voxel_size) const {
  VoxelCloudBuilder builder(voxel_size);
  for (const auto& kf : keyframes_) builder.add(*kf);
  return builder.cloud();
}

std::unique_ptr<octomap::ColorOcTree> MapFusion::octree(double resolution) const {
  auto tree = std::make_unique<octomap::ColorOcTree>(resolution);
  const double max_range = map_config_.max_range_eye_heights * resolution / map_config_.octree_eye_heights;
  for (const auto& kf : keyframes_) insertKeyframe(*tree, *kf, max_range);
  updateInnerNodes(*tree);
  return tree;
}

FloorGrid MapFusion::floorGrid(const CoverageGrid& grid, double resolution) const {
  FloorGridBuilder builder(grid, resolution, collision_config_);
  for (const auto& kf : keyframes_) builder.add(*kf);
  return builder.grid();
}

uint64_t newKeyframeId() {
  // Random high half per process, counter low half: ids of two episodes, or of two runs
  // of the explorer, do not meet, so a mirror never takes a stale keyframe for a kept one.
  static const uint64_t process = static_cast<uint64_t>(std::random_device{}()) << 32;
  static std::atomic<uint64_t> next{0};
  return process | (next++ & 0xffffffffULL);
}

}  // namespace valerant
