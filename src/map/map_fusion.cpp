#include "valerant/map/map_fusion.h"

#include <octomap/ColorOcTree.h>
#include <algorithm>
#include <cmath>
#include <tuple>
#include <unordered_map>

namespace valerant {

MapFusion::MapFusion(const MapConfig& map_config, const CollisionConfig& collision_config)
    : map_config_(map_config), collision_config_(collision_config) {}

void MapFusion::fuse(const KeyframeCloud& cloud, const FloorPlane& floor) {
  auto kf = std::make_shared<FusedKeyframe>();
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
  // Written by hand, not pcl::VoxelGrid: PCL indexes voxels with 32-bit integers over the
  // cloud's bounding box and gives up (empty output, no leaf layout) when a few far
  // points of a drifting monocular map make that box too large for the leaf; a hash of
  // 64-bit voxel keys has no such limit. Voxels come out in order of first appearance,
  // so the output is deterministic.
  struct Voxel {
    Eigen::Matrix<int64_t, 3, 1> key;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    Eigen::Vector4d colour_confidence = Eigen::Vector4d::Zero();
    double h = 0;
    int count = 0;
  };
  struct KeyHash {
    size_t operator()(const Eigen::Matrix<int64_t, 3, 1>& k) const {
      return std::hash<int64_t>()(k.x() * 73856093LL ^ k.y() * 19349663LL ^ k.z() * 83492791LL);
    }
  };
  std::unordered_map<Eigen::Matrix<int64_t, 3, 1>, size_t, KeyHash> index;
  const float inverse_leaf = static_cast<float>(1.0 / voxel_size);
  std::vector<Voxel> voxels;
  for (const auto& kf : keyframes_) {
    for (const auto& p : kf->points) {
      const Eigen::Vector3d x = p.position.cast<double>();
      // Binned in float like PCL, so points on voxel borders fall the same way.
      const Eigen::Matrix<int64_t, 3, 1> key = (p.position * inverse_leaf).array().floor().cast<int64_t>();
      const auto [it, added] = index.try_emplace(key, voxels.size());
      if (added) voxels.emplace_back().key = key;
      Voxel& v = voxels[it->second];
      v.position += x;
      v.colour_confidence += Eigen::Vector4d(p.rgb[0], p.rgb[1], p.rgb[2], p.confidence);
      v.h += p.h;
      ++v.count;
    }
  }
  std::sort(voxels.begin(), voxels.end(), [](const Voxel& a, const Voxel& b) {
    return std::tie(a.key.z(), a.key.y(), a.key.x()) < std::tie(b.key.z(), b.key.y(), b.key.x());
  });
  std::vector<FusedPoint> out;
  out.reserve(voxels.size());
  for (const Voxel& v : voxels) {
    const Eigen::Vector4d mean = v.colour_confidence / v.count;
    FusedPoint p;
    p.position = (v.position / v.count).cast<float>();
    p.rgb = {static_cast<uint8_t>(std::lround(mean[0])), static_cast<uint8_t>(std::lround(mean[1])),
             static_cast<uint8_t>(std::lround(mean[2]))};
    p.confidence = static_cast<float>(mean[3]);
    p.h = static_cast<float>(v.h / v.count);
    out.push_back(p);
  }
  return out;
}

std::unique_ptr<octomap::ColorOcTree> MapFusion::octree(double resolution) const {
  auto tree = std::make_unique<octomap::ColorOcTree>(resolution);
  for (const auto& kf : keyframes_) {
    octomap::Pointcloud cloud;
    for (const auto& p : kf->points) cloud.push_back(p.position.x(), p.position.y(), p.position.z());
    const Eigen::Vector3d c = kf->camera_to_map.translation();
    const double max_range = map_config_.max_range_eye_heights * resolution / map_config_.octree_eye_heights;
    tree->insertPointCloud(cloud, octomap::point3d(c.x(), c.y(), c.z()), max_range, false, true);
    for (const auto& p : kf->points)
      tree->averageNodeColor(p.position.x(), p.position.y(), p.position.z(), p.rgb[0], p.rgb[1], p.rgb[2]);
  }
  tree->updateInnerOccupancy();
  return tree;
}

FloorGrid MapFusion::floorGrid(const CoverageGrid& grid, double resolution) const {
  FloorGrid g;
  const double extent = grid.size() * grid.cellSize();
  g.resolution = resolution;
  g.width = g.height = static_cast<int>(std::ceil(extent / resolution));
  g.origin = Eigen::Vector2d::Constant(-0.5 * extent);
  g.cells.assign(static_cast<size_t>(g.width) * g.height, -1);
  for (const auto& kf : keyframes_) {
    for (const auto& p : kf->points) {
      const Eigen::Vector2d uv = grid.floorCoordinates(p.position.cast<double>()) - g.origin;
      const int col = static_cast<int>(std::floor(uv.x() / resolution));
      const int row = static_cast<int>(std::floor(uv.y() / resolution));
      if (col < 0 || row < 0 || col >= g.width || row >= g.height) continue;
      int8_t& cell = g.cells[static_cast<size_t>(row) * g.width + col];
      if (p.h >= collision_config_.height_low && p.h <= collision_config_.height_high) {
        cell = 100;
      } else if (std::abs(p.h) < collision_config_.height_low && cell != 100) {
        cell = 0;
      }
    }
  }
  return g;
}

}  // namespace valerant
