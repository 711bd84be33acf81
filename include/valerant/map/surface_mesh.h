#pragma once
// A triangulated surface of the fused map, vertex-coloured. Built by PCL's greedy
// projection triangulation (GP3) over the voxel cloud: it keeps the cloud's points as
// vertices (so their colours and heights carry over) and leaves holes where nothing
// was seen, instead of inventing closed surfaces as Poisson reconstruction does on
// partial indoor scans. Normals are PCA normals turned toward the nearest camera that
// could have seen the point, so triangles face the explored space.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/map/map_fusion.h"

namespace valerant {

struct SurfaceMesh {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;  // unit
  std::vector<std::array<uint8_t, 3>> colours;
  std::vector<float> heights;            // floor-normalised height h of each vertex
  std::vector<std::array<uint32_t, 3>> triangles;  // counter-clockwise seen from the normal side
};

struct MeshParams {
  double max_edge = 0;            // map units: GP3 search radius
  double mu = 2.5;
  int max_neighbours = 100;
  double max_surface_angle_deg = 45;
  double min_angle_deg = 10;
  double max_angle_deg = 120;
  int normal_neighbours = 16;
};

// The cloud a mesh is built from: `cloud` (the voxel cloud at leaf `voxel`) when it has
// at most `max_points` points, else `voxel_cloud(leaf)` at the first leaf voxel x 1.25^k
// (k = 1, 2, ..., at most 64) that has. GP3's time grows with its points.
struct MeshCloud {
  std::vector<FusedPoint> points;
  double leaf = 0;  // map units
};
MeshCloud meshCloud(std::vector<FusedPoint> cloud, double voxel, size_t max_points,
                    const std::function<std::vector<FusedPoint>(double)>& voxel_cloud);

// Params from the config for a cloud voxel-filtered with leaf `voxel_size` (map units).
MeshParams meshParams(const ExportConfig& config, double voxel_size);

// Triangulates `cloud`; `viewpoints` are the camera centres that observed it. Vertices
// no triangle uses are left out. An empty or too small cloud gives an empty mesh.
SurfaceMesh triangulateCloud(const std::vector<FusedPoint>& cloud, const std::vector<Eigen::Vector3d>& viewpoints,
                             const MeshParams& params);

// The mesh moved by a similarity (positions transformed, normals rotated).
SurfaceMesh transformMesh(const SurfaceMesh& mesh, const Eigen::Affine3d& similarity);

// The mesh without triangles that touch a vertex higher than `max_height` (h), e.g.
// ceilings cut away for a view from above; unused vertices are left out.
SurfaceMesh cutAbove(const SurfaceMesh& mesh, float max_height);

}  // namespace valerant
