#pragma once
// Triangle soup of every drawable BSP face (polygons, meshes, tessellated patches),
// one draw surface per face so the renderer can batch by (shader, lightmap) and cull
// by leaf, and the surface sampler can weight by area. Faces that are never drawn
// (nodraw, billboards, fog) get an empty surface.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "valerant/world/quake3/bsp.h"

namespace valerant::quake3 {

struct DrawSurface {
  int shader = 0;
  int lightmap = -1;
  uint32_t first_index = 0;
  uint32_t num_indices = 0;  // 0: not drawn
  bool sky = false;
  Eigen::AlignedBox3f bounds;
};

struct MapGeometry {
  std::vector<BspVertex> vertices;
  std::vector<uint32_t> indices;      // triangles
  std::vector<DrawSurface> surfaces;  // surfaces[i] belongs to BspMap::faces[i]
  Eigen::AlignedBox3f bounds;         // of all drawn non-sky triangles
};

// `patch_level`: segments per Bezier block edge.
MapGeometry buildMapGeometry(const BspMap& map, int patch_level);

}  // namespace valerant::quake3
