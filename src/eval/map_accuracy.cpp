#include "valerant/eval/map_accuracy.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "valerant/world/quake3/units.h"

namespace valerant {
namespace {

pcl::PointCloud<pcl::PointXYZ>::Ptr toCloud(const std::vector<Eigen::Vector3d>& points) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  for (const auto& p : points) cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  return cloud;
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return std::nan("");
  const size_t i = std::min(values.size() - 1, static_cast<size_t>(q * values.size()));
  std::nth_element(values.begin(), values.begin() + i, values.end());
  return values[i];
}

}  // namespace

MapAccuracy mapAccuracy(const std::vector<Eigen::Vector3d>& map_points_m,
                        const std::vector<quake3::SurfaceSample>& samples_units,
                        const std::vector<FrameTruth>& committed, const CameraIntrinsics& k,
                        const MapAccuracyParams& params) {
  MapAccuracy a;
  a.map_points = static_cast<int>(map_points_m.size());
  std::vector<Eigen::Vector3d> samples;
  for (const auto& s : samples_units) samples.push_back(s.position.cast<double>() / quake3::kUnitsPerMetre);
  if (samples.empty()) return a;

  std::vector<int> index(1);
  std::vector<float> distance2(1);
  if (!map_points_m.empty()) {
    pcl::KdTreeFLANN<pcl::PointXYZ> surface;
    surface.setInputCloud(toCloud(samples));
    std::vector<double> distances;
    for (const auto& p : map_points_m) {
      if (surface.nearestKSearch(pcl::PointXYZ(p.x(), p.y(), p.z()), 1, index, distance2) == 1)
        distances.push_back(std::sqrt(distance2[0]));
    }
    a.median_m = quantile(distances, 0.5);
    a.p90_m = quantile(distances, 0.9);
  }

  bool any_depth = false;
  for (const FrameTruth& frame : committed) any_depth |= !frame.depth_m.empty();
  if (!any_depth) {
    a.completeness_percent = std::numeric_limits<double>::quiet_NaN();
    return a;
  }
  std::vector<bool> seen(samples.size(), false);
  for (size_t f = 0; f < committed.size(); f += params.frame_stride) {
    const FrameTruth& frame = committed[f];
    if (frame.depth_m.empty()) continue;
    Eigen::Isometry3d world_to_camera = frame.camera_to_world.inverse();
    for (size_t i = 0; i < samples.size(); ++i) {
      if (seen[i]) continue;
      const Eigen::Vector3d c = world_to_camera * (samples[i] * quake3::kUnitsPerMetre) / quake3::kUnitsPerMetre;
      if (c.z() <= 0) continue;
      const int u = static_cast<int>(std::lround(k.fx * c.x() / c.z() + k.cx));
      const int v = static_cast<int>(std::lround(k.fy * c.y() / c.z() + k.cy));
      if (u < 0 || v < 0 || u >= frame.depth_m.cols || v >= frame.depth_m.rows) continue;
      const float d = frame.depth_m.at<float>(v, u);
      seen[i] = std::isfinite(d) && std::abs(d - c.z()) <= params.depth_agreement * c.z();
    }
  }
  pcl::KdTreeFLANN<pcl::PointXYZ> map_tree;
  if (!map_points_m.empty()) map_tree.setInputCloud(toCloud(map_points_m));
  int covered = 0;
  for (size_t i = 0; i < samples.size(); ++i) {
    if (!seen[i]) continue;
    ++a.seen_samples;
    if (map_points_m.empty()) continue;
    const auto& s = samples[i];
    if (map_tree.nearestKSearch(pcl::PointXYZ(s.x(), s.y(), s.z()), 1, index, distance2) == 1 &&
        std::sqrt(distance2[0]) <= params.within_m)
      ++covered;
  }
  a.completeness_percent = a.seen_samples ? 100.0 * covered / a.seen_samples : 0;
  return a;
}

}  // namespace valerant
