#pragma once
// Tessellation of Quake III Bezier patches (BSP face type 2) into triangles.
// A patch is a grid of width x height control points (both odd); every 3x3 block
// is one biquadratic Bezier surface. The game subdivides adaptively; we use a fixed
// level per block, which is all a renderer and a surface sampler need.
#include <vector>

#include "valerant/world/quake3/bsp.h"

namespace valerant::quake3 {

struct TriangleMesh {
  std::vector<BspVertex> vertices;
  std::vector<int> indices;  // three per triangle, wound like the BSP's own mesh faces
};

// `control` holds width*height points, row-major (row = v direction).
// `level` = segments per 3x3 block edge (>= 1). Throws InputError for even or
// too-small sizes.
TriangleMesh tessellatePatch(const std::vector<BspVertex>& control, int width, int height,
                             int level);

}  // namespace valerant::quake3
