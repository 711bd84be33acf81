#include "valerant/eval/map_accuracy.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "valerant/common/median.h"
#include "valerant/world/quake3/units.h"

namespace valerant {
namespace {

pcl::PointCloud<pcl::PointXYZ>::Ptr toCloud(const std::vector<Eigen::Vector3d>& points) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  for (const auto& p : points) cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  return cloud;
}

// The surface samples binned in cubes, so that a frame tests only the samples within
// its reach (the engine levels are far larger than what one view sees).
class SampleCells {
 public:
  SampleCells(const std::vector<Eigen::Vector3d>& samples, double cell) : cell_(cell) {
    lo_ = hi_ = samples.front();
    for (const auto& s : samples) lo_ = lo_.cwiseMin(s), hi_ = hi_.cwiseMax(s);
    for (int a = 0; a < 3; ++a) dims_[a] = static_cast<int>(std::floor((hi_[a] - lo_[a]) / cell_)) + 1;
    members_.resize(static_cast<size_t>(dims_[0]) * dims_[1] * dims_[2]);
    for (size_t i = 0; i < samples.size(); ++i) {
      Eigen::Vector3i c;
      for (int a = 0; a < 3; ++a) c[a] = std::min(dims_[a] - 1, static_cast<int>((samples[i][a] - lo_[a]) / cell_));
      members_[flat(c)].push_back(i);
    }
  }
  // Calls f(i) for every sample i in the cells meeting the box centre +- radius (and
  // maybe a few more): a superset of the samples within `radius` of `centre`. Cells for
  // which may_hold(cell centre, radius of the sphere around the cell) is false are
  // skipped.
  template <typename Keep, typename F>
  void forEachNear(const Eigen::Vector3d& centre, double radius, Keep&& may_hold, F&& f) const {
    const double cell_radius = 0.5 * std::sqrt(3.0) * cell_;
    Eigen::Vector3i from, to;
    for (int a = 0; a < 3; ++a) {
      from[a] = std::max(0, static_cast<int>(std::floor((centre[a] - radius - lo_[a]) / cell_)));
      to[a] = std::min(dims_[a] - 1, static_cast<int>(std::floor((centre[a] + radius - lo_[a]) / cell_)));
      if (from[a] > to[a]) return;
    }
    for (int x = from[0]; x <= to[0]; ++x)
      for (int y = from[1]; y <= to[1]; ++y)
        for (int z = from[2]; z <= to[2]; ++z) {
          const std::vector<size_t>& members = members_[flat({x, y, z})];
          if (members.empty()) continue;
          const Eigen::Vector3d cell_centre = lo_ + cell_ * (Eigen::Vector3d(x, y, z).array() + 0.5).matrix();
          if (!may_hold(cell_centre, cell_radius)) continue;
          for (size_t i : members) f(i);
        }
  }

 private:
  size_t flat(const Eigen::Vector3i& c) const {
    return (static_cast<size_t>(c[0]) * dims_[1] + c[1]) * dims_[2] + c[2];
  }
  double cell_;
  Eigen::Vector3d lo_, hi_;
  int dims_[3] = {1, 1, 1};
  std::vector<std::vector<size_t>> members_;
};

// How far from the camera a sample can be and still be seen in `frame`: its depth z is
// at most the frame's largest finite depth / (1 - agreement), and its pixel lies inside
// the image, so its ray is at most the corner ray's length per unit z (half a pixel
// more for the rounding). 1 % more for floating-point rounding; 0 when the frame has no
// finite depth (it sees nothing).
double reachOf(const cv::Mat& depth_m, const CameraIntrinsics& k, double agreement) {
  double max_depth = 0;
  for (int v = 0; v < depth_m.rows; ++v) {
    const float* row = depth_m.ptr<float>(v);
    for (int u = 0; u < depth_m.cols; ++u)
      if (std::isfinite(row[u])) max_depth = std::max(max_depth, static_cast<double>(row[u]));
  }
  if (!(agreement < 1)) return std::numeric_limits<double>::infinity();
  const double ax = (std::max(k.cx, depth_m.cols - k.cx) + 0.5) / k.fx;
  const double ay = (std::max(k.cy, depth_m.rows - k.cy) + 0.5) / k.fy;
  return 1.01 * max_depth / (1 - agreement) * std::sqrt(1 + ax * ax + ay * ay);
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
  // A sample is seen when any committed frame sees it: frames in any order, and in each
  // only the samples within its reach (reachOf), give the same flags as testing all.
  std::vector<bool> seen(samples.size(), false);
  constexpr double kCellMetres = 4;
  const SampleCells cells(samples, kCellMetres);

  for (size_t f = 0; f < committed.size(); f += params.frame_stride) {
    const FrameTruth& frame = committed[f];
    if (frame.depth_m.empty()) continue;
    const double reach = reachOf(frame.depth_m, k, params.depth_agreement);
    if (!(reach > 0)) continue;
    Eigen::Isometry3d world_to_camera = frame.camera_to_world.inverse();
    // The view's four sides: lround keeps u in [0, cols) for x / z in
    // [-0.5 - cx, cols - 0.5 - cx) / fx (and v alike); half a pixel wider each way.
    // {slope, axis (0: x, 1: y), sign}: inside where sign * (lateral - slope z) >= 0.
    const struct {
      double slope;
      int axis;
      double sign;
    } side_planes[4] = {{(-1.0 - k.cx) / k.fx, 0, 1},
                        {(frame.depth_m.cols - k.cx) / k.fx, 0, -1},
                        {(-1.0 - k.cy) / k.fy, 1, 1},
                        {(frame.depth_m.rows - k.cy) / k.fy, 1, -1}};
    // A cell whose sphere lies wholly behind the camera or wholly outside one side of the
    // view (its planes widened by half a pixel, and the sphere by 1 %) holds no sample
    // that can pass the test below.
    auto inView = [&](const Eigen::Vector3d& centre_m, double radius_m) {
      const Eigen::Vector3d c = world_to_camera * (centre_m * quake3::kUnitsPerMetre) / quake3::kUnitsPerMetre;
      const double r = 1.01 * radius_m;
      if (c.z() < -r) return false;
      for (const auto& [slope, axis, sign] : side_planes) {
        const double lateral = axis == 0 ? c.x() : c.y();
        if (sign * (lateral - slope * c.z()) / std::sqrt(1 + slope * slope) < -r) return false;
      }
      return true;
    };
    cells.forEachNear(frame.camera_to_world.translation() / quake3::kUnitsPerMetre, reach, inView, [&](size_t i) {
      if (seen[i]) return;
      const Eigen::Vector3d c = world_to_camera * (samples[i] * quake3::kUnitsPerMetre) / quake3::kUnitsPerMetre;
      if (c.z() <= 0) return;
      const int u = static_cast<int>(std::lround(k.fx * c.x() / c.z() + k.cx));
      const int v = static_cast<int>(std::lround(k.fy * c.y() / c.z() + k.cy));
      if (u < 0 || v < 0 || u >= frame.depth_m.cols || v >= frame.depth_m.rows) return;
      const float d = frame.depth_m.at<float>(v, u);
      seen[i] = std::isfinite(d) && std::abs(d - c.z()) <= params.depth_agreement * c.z();
    });
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
