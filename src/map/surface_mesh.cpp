#include "valerant/map/surface_mesh.h"

#include <pcl/common/io.h>
#include <pcl/features/normal_3d.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/surface/gp3.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace valerant {
namespace {

constexpr double kDegrees = M_PI / 180.0;

// The triangles `keep` accepts, with only the vertices they use (renumbered).
template <typename Keep>
SurfaceMesh keepTriangles(const SurfaceMesh& mesh, Keep keep) {
  SurfaceMesh out;
  std::vector<int64_t> index(mesh.positions.size(), -1);
  auto vertex = [&](uint32_t v) {
    if (index[v] < 0) {
      index[v] = static_cast<int64_t>(out.positions.size());
      out.positions.push_back(mesh.positions[v]);
      out.normals.push_back(mesh.normals[v]);
      out.colours.push_back(mesh.colours[v]);
      out.heights.push_back(mesh.heights[v]);
    }
    return static_cast<uint32_t>(index[v]);
  };
  for (const auto& t : mesh.triangles)
    if (keep(t)) out.triangles.push_back({vertex(t[0]), vertex(t[1]), vertex(t[2])});
  return out;
}

}  // namespace

MeshCloud meshCloud(std::vector<FusedPoint> cloud, double voxel, size_t max_points,
                    const std::function<std::vector<FusedPoint>(double)>& voxel_cloud) {
  constexpr int kMaxCoarsenings = 64;  // 1.25^64 ~ 1.6e6 times the leaf
  MeshCloud out{std::move(cloud), voxel};
  for (int k = 0; k < kMaxCoarsenings && out.points.size() > max_points; ++k) {
    out.leaf *= 1.25;
    out.points = voxel_cloud(out.leaf);
  }
  return out;
}

MeshParams meshParams(const ExportConfig& config, double voxel_size) {
  MeshParams p;
  p.max_edge = config.mesh_radius_voxels * voxel_size;
  p.mu = config.mesh_mu;
  p.max_neighbours = config.mesh_max_neighbours;
  p.max_surface_angle_deg = config.mesh_max_surface_angle_deg;
  p.min_angle_deg = config.mesh_min_angle_deg;
  p.max_angle_deg = config.mesh_max_angle_deg;
  p.normal_neighbours = config.normal_neighbours;
  return p;
}

SurfaceMesh triangulateCloud(const std::vector<FusedPoint>& cloud, const std::vector<Eigen::Vector3d>& viewpoints,
                             const MeshParams& params) {
  if (cloud.size() < static_cast<size_t>(params.normal_neighbours) || viewpoints.empty()) return {};
  pcl::PointCloud<pcl::PointXYZ>::Ptr points(new pcl::PointCloud<pcl::PointXYZ>);
  for (const auto& p : cloud) points->push_back(pcl::PointXYZ(p.position.x(), p.position.y(), p.position.z()));

  pcl::PointCloud<pcl::Normal> normals;
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
  estimation.setInputCloud(points);
  estimation.setSearchMethod(pcl::search::KdTree<pcl::PointXYZ>::Ptr(new pcl::search::KdTree<pcl::PointXYZ>));
  estimation.setKSearch(params.normal_neighbours);
  estimation.compute(normals);

  // Turn each normal toward the nearest camera centre: the camera most likely to have
  // seen the point, on the open side of the surface.
  pcl::PointCloud<pcl::PointXYZ>::Ptr cameras(new pcl::PointCloud<pcl::PointXYZ>);
  for (const auto& c : viewpoints) cameras->push_back(pcl::PointXYZ(c.x(), c.y(), c.z()));
  pcl::KdTreeFLANN<pcl::PointXYZ> nearest_camera;
  nearest_camera.setInputCloud(cameras);
  pcl::PointCloud<pcl::PointNormal>::Ptr oriented(new pcl::PointCloud<pcl::PointNormal>);
  std::vector<size_t> source;  // oriented point -> cloud index (points without a normal are dropped)
  std::vector<int> found(1);
  std::vector<float> distance(1);
  for (size_t i = 0; i < points->size(); ++i) {
    Eigen::Vector3f n = normals[i].getNormalVector3fMap();
    if (!n.allFinite()) continue;
    nearest_camera.nearestKSearch((*points)[i], 1, found, distance);
    if (n.dot((*cameras)[found[0]].getVector3fMap() - (*points)[i].getVector3fMap()) < 0) n = -n;
    pcl::PointNormal q;
    q.getVector3fMap() = (*points)[i].getVector3fMap();
    q.getNormalVector3fMap() = n;
    oriented->push_back(q);
    source.push_back(i);
  }
  if (oriented->size() < 3) return {};

  pcl::GreedyProjectionTriangulation<pcl::PointNormal> gp3;
  gp3.setSearchRadius(params.max_edge);
  gp3.setMu(params.mu);
  gp3.setMaximumNearestNeighbors(params.max_neighbours);
  gp3.setMaximumSurfaceAngle(params.max_surface_angle_deg * kDegrees);
  gp3.setMinimumAngle(params.min_angle_deg * kDegrees);
  gp3.setMaximumAngle(params.max_angle_deg * kDegrees);
  gp3.setNormalConsistency(true);  // oriented above
  gp3.setInputCloud(oriented);
  gp3.setSearchMethod(pcl::search::KdTree<pcl::PointNormal>::Ptr(new pcl::search::KdTree<pcl::PointNormal>));
  std::vector<pcl::Vertices> polygons;
  gp3.reconstruct(polygons);

  SurfaceMesh all;
  for (size_t k = 0; k < oriented->size(); ++k) {
    const FusedPoint& p = cloud[source[k]];
    all.positions.push_back(p.position);
    all.normals.push_back((*oriented)[k].getNormalVector3fMap());
    all.colours.push_back(p.rgb);
    all.heights.push_back(p.h);
  }
  for (const auto& poly : polygons) {
    if (poly.vertices.size() != 3) continue;
    std::array<uint32_t, 3> t{static_cast<uint32_t>(poly.vertices[0]), static_cast<uint32_t>(poly.vertices[1]),
                              static_cast<uint32_t>(poly.vertices[2])};
    const Eigen::Vector3f ab = all.positions[t[1]] - all.positions[t[0]];
    const Eigen::Vector3f ac = all.positions[t[2]] - all.positions[t[0]];
    const Eigen::Vector3f face = ab.cross(ac);
    // GP3 joins collinear points on regular rows (voxel centres on a plane): no area.
    if (face.norm() <= std::numeric_limits<float>::epsilon() * std::max(ab.squaredNorm(), ac.squaredNorm())) continue;
    // Counter-clockwise seen from the normals' side, so renderers and engines see the
    // front face from the explored space.
    if (face.dot(all.normals[t[0]] + all.normals[t[1]] + all.normals[t[2]]) < 0) std::swap(t[1], t[2]);
    all.triangles.push_back(t);
  }
  return keepTriangles(all, [](const std::array<uint32_t, 3>&) { return true; });
}

SurfaceMesh transformMesh(const SurfaceMesh& mesh, const Eigen::Affine3d& similarity) {
  SurfaceMesh out = mesh;
  const Eigen::Affine3f t = similarity.cast<float>();
  const Eigen::Matrix3f rotation = t.linear() / t.linear().col(0).norm();
  for (auto& p : out.positions) p = t * p;
  for (auto& n : out.normals) n = (rotation * n).normalized();
  return out;
}

SurfaceMesh cutAbove(const SurfaceMesh& mesh, float max_height) {
  return keepTriangles(mesh, [&](const std::array<uint32_t, 3>& t) {
    return mesh.heights[t[0]] <= max_height && mesh.heights[t[1]] <= max_height && mesh.heights[t[2]] <= max_height;
  });
}

}  // namespace valerant
