#include "valerant/map/map_fusion.h"

#define PCL_NO_PRECOMPILE
#include <octomap/ColorOcTree.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_types.h>

#include <cmath>

namespace valerant {
namespace {

// PCL point carrying what the map needs per point, so VoxelGrid averages it all.
struct PointMap {
  PCL_ADD_POINT4D;
  float r, g, b;  // floats, not packed rgb: VoxelGrid averages fields arithmetically
  float confidence;
  float h;
  PCL_MAKE_ALIGNED_OPERATOR_NEW
};

}  // namespace
}  // namespace valerant

POINT_CLOUD_REGISTER_POINT_STRUCT(valerant::PointMap,
                                  (float, x, x)(float, y, y)(float, z, z)(float, r, r)(float, g, g)(float, b, b)(
                                      float, confidence, confidence)(float, h, h))

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
  pcl::PointCloud<PointMap>::Ptr all(new pcl::PointCloud<PointMap>);
  all->reserve(pointCount());
  for (const auto& kf : keyframes_) {
    for (const auto& p : kf->points) {
      PointMap m;
      m.x = p.position.x(), m.y = p.position.y(), m.z = p.position.z();
      m.r = p.rgb[0], m.g = p.rgb[1], m.b = p.rgb[2];
      m.confidence = p.confidence;
      m.h = p.h;
      all->push_back(m);
    }
  }
  std::vector<FusedPoint> out;
  if (all->empty()) return out;
  pcl::PointCloud<PointMap> filtered;
  pcl::VoxelGrid<PointMap> grid;
  grid.setInputCloud(all);
  grid.setLeafSize(voxel_size, voxel_size, voxel_size);
  grid.setDownsampleAllData(true);
  grid.filter(filtered);
  out.reserve(filtered.size());
  for (const auto& m : filtered) {
    FusedPoint p;
    p.position = {m.x, m.y, m.z};
    p.rgb = {static_cast<uint8_t>(std::lround(m.r)), static_cast<uint8_t>(std::lround(m.g)),
             static_cast<uint8_t>(std::lround(m.b))};
    p.confidence = m.confidence;
    p.h = m.h;
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
