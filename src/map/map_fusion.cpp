#include "valerant/map/map_fusion.h"

#include <octomap/ColorOcTree.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_types.h>

#include <cmath>

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
  pcl::PointCloud<pcl::PointXYZ>::Ptr all(new pcl::PointCloud<pcl::PointXYZ>);
  std::vector<const FusedPoint*> source;
  all->reserve(pointCount());
  for (const auto& kf : keyframes_) {
    for (const auto& p : kf->points) {
      all->push_back(pcl::PointXYZ(p.position.x(), p.position.y(), p.position.z()));
      source.push_back(&p);
    }
  }
  std::vector<FusedPoint> out;
  if (all->empty()) return out;
  // PCL picks the voxels and their centroids; colour, confidence and height are
  // averaged per voxel here through its leaf layout (VoxelGrid only averages the
  // fields of PCL's own point types).
  pcl::PointCloud<pcl::PointXYZ> centroids;
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setInputCloud(all);
  grid.setLeafSize(voxel_size, voxel_size, voxel_size);
  grid.setSaveLeafLayout(true);
  grid.filter(centroids);
  std::vector<Eigen::Vector4d> colour_confidence(centroids.size(), Eigen::Vector4d::Zero());
  std::vector<double> heights(centroids.size(), 0.0);
  std::vector<int> counts(centroids.size(), 0);
  for (size_t i = 0; i < all->size(); ++i) {
    const int v = grid.getCentroidIndex((*all)[i]);
    if (v < 0) continue;
    const FusedPoint& p = *source[i];
    colour_confidence[v] += Eigen::Vector4d(p.rgb[0], p.rgb[1], p.rgb[2], p.confidence);
    heights[v] += p.h;
    ++counts[v];
  }
  out.reserve(centroids.size());
  for (size_t v = 0; v < centroids.size(); ++v) {
    if (counts[v] == 0) continue;
    const Eigen::Vector4d mean = colour_confidence[v] / counts[v];
    FusedPoint p;
    p.position = centroids[v].getVector3fMap();
    p.rgb = {static_cast<uint8_t>(std::lround(mean[0])), static_cast<uint8_t>(std::lround(mean[1])),
             static_cast<uint8_t>(std::lround(mean[2]))};
    p.confidence = static_cast<float>(mean[3]);
    p.h = static_cast<float>(heights[v] / counts[v]);
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
