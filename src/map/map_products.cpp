#include "valerant/map/map_products.h"

#include <octomap/ColorOcTree.h>

#include <algorithm>
#include <cmath>
#include <tuple>

namespace valerant {

// Written by hand, not pcl::VoxelGrid: PCL indexes voxels with 32-bit integers over the
// cloud's bounding box and gives up (empty output, no leaf layout) when a few far
// points of a drifting monocular map make that box too large for the leaf; a hash of
// 64-bit voxel keys has no such limit, and it can be extended keyframe by keyframe.
VoxelCloudBuilder::VoxelCloudBuilder(double voxel_size) : inverse_leaf_(static_cast<float>(1.0 / voxel_size)) {}

size_t VoxelCloudBuilder::KeyHash::operator()(const Key& k) const {
  return std::hash<int64_t>()(k.x() * 73856093LL ^ k.y() * 19349663LL ^ k.z() * 83492791LL);
}

void VoxelCloudBuilder::add(const FusedKeyframe& keyframe) {
  for (const auto& p : keyframe.points) {
    // Binned in float like PCL, so points on voxel borders fall the same way.
    const Key key = (p.position * inverse_leaf_).array().floor().cast<int64_t>();
    const auto [it, added] = index_.try_emplace(key, voxels_.size());
    if (added) voxels_.emplace_back().key = key;
    Voxel& v = voxels_[it->second];
    v.position += p.position.cast<double>();
    v.colour_confidence += Eigen::Vector4d(p.rgb[0], p.rgb[1], p.rgb[2], p.confidence);
    v.h += p.h;
    ++v.count;
  }
}

std::vector<FusedPoint> VoxelCloudBuilder::cloud() const {
  std::vector<const Voxel*> sorted;
  sorted.reserve(voxels_.size());
  for (const Voxel& v : voxels_) sorted.push_back(&v);
  std::sort(sorted.begin(), sorted.end(), [](const Voxel* a, const Voxel* b) {
    return std::tie(a->key.z(), a->key.y(), a->key.x()) < std::tie(b->key.z(), b->key.y(), b->key.x());
  });
  std::vector<FusedPoint> out;
  out.reserve(sorted.size());
  for (const Voxel* v : sorted) {
    const Eigen::Vector4d mean = v->colour_confidence / v->count;
    FusedPoint p;
    p.position = (v->position / v->count).cast<float>();
    p.rgb = {static_cast<uint8_t>(std::lround(mean[0])), static_cast<uint8_t>(std::lround(mean[1])),
             static_cast<uint8_t>(std::lround(mean[2]))};
    p.confidence = static_cast<float>(mean[3]);
    p.h = static_cast<float>(v->h / v->count);
    out.push_back(p);
  }
  return out;
}

void insertKeyframe(octomap::ColorOcTree& tree, const FusedKeyframe& keyframe, double max_range) {
  octomap::Pointcloud cloud;
  for (const auto& p : keyframe.points) cloud.push_back(p.position.x(), p.position.y(), p.position.z());
  const Eigen::Vector3d c = keyframe.camera_to_map.translation();
  // lazy_eval: inner nodes are left to updateInnerNodes, once after a batch. Updating
  // them on every insertion also pruned each node and expanded it again at the next ray
  // through it: 2.3-2.7 times the time for the same leaf occupancies (docs/outputs.md).
  tree.insertPointCloud(cloud, octomap::point3d(c.x(), c.y(), c.z()), max_range, true, true);
  for (const auto& p : keyframe.points)
    tree.averageNodeColor(p.position.x(), p.position.y(), p.position.z(), p.rgb[0], p.rgb[1], p.rgb[2]);
}

void updateInnerNodes(octomap::ColorOcTree& tree) {
  if (tree.getRoot() != nullptr) tree.updateInnerOccupancy();
}

FloorGridBuilder::FloorGridBuilder(const CoverageGrid& grid, double resolution, const CollisionConfig& heights)
    : grid_(grid), height_low_(heights.height_low), height_high_(heights.height_high) {
  const double extent = grid.size() * grid.cellSize();
  floor_.resolution = resolution;
  floor_.width = floor_.height = static_cast<int>(std::ceil(extent / resolution));
  floor_.origin = Eigen::Vector2d::Constant(-0.5 * extent);
  floor_.cells.assign(static_cast<size_t>(floor_.width) * floor_.height, -1);
}

void FloorGridBuilder::add(const FusedKeyframe& keyframe) {
  for (const auto& p : keyframe.points) {
    const Eigen::Vector2d uv = grid_.floorCoordinates(p.position.cast<double>()) - floor_.origin;
    const int col = static_cast<int>(std::floor(uv.x() / floor_.resolution));
    const int row = static_cast<int>(std::floor(uv.y() / floor_.resolution));
    if (col < 0 || row < 0 || col >= floor_.width || row >= floor_.height) continue;
    int8_t& cell = floor_.cells[static_cast<size_t>(row) * floor_.width + col];
    if (p.h >= height_low_ && p.h <= height_high_) {
      cell = 100;
    } else if (std::abs(p.h) < height_low_ && cell != 100) {
      cell = 0;
    }
  }
}

}  // namespace valerant
