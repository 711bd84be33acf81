#include "valerant/world/quake3/patch.h"

#include "valerant/common/error.h"

namespace valerant::quake3 {
namespace {

// Weighted sum of three vertices (quadratic Bernstein weights), every attribute.
BspVertex blend(const BspVertex& a, const BspVertex& b, const BspVertex& c, float wa, float wb,
                float wc) {
  BspVertex v;
  v.position = wa * a.position + wb * b.position + wc * c.position;
  v.texcoord = wa * a.texcoord + wb * b.texcoord + wc * c.texcoord;
  v.lmcoord = wa * a.lmcoord + wb * b.lmcoord + wc * c.lmcoord;
  v.normal = wa * a.normal + wb * b.normal + wc * c.normal;
  for (int k = 0; k < 4; ++k)
    v.color[k] = static_cast<uint8_t>(wa * a.color[k] + wb * b.color[k] + wc * c.color[k] + 0.5f);
  return v;
}

}  // namespace

TriangleMesh tessellatePatch(const std::vector<BspVertex>& control, int width, int height,
                             int level) {
  const std::string what = "patch " + std::to_string(width) + "x" + std::to_string(height);
  if (width < 3 || height < 3 || width % 2 == 0 || height % 2 == 0)
    throw InputError(what, "control grid must be odd and at least 3x3");
  if (static_cast<size_t>(width) * height != control.size())
    throw InputError(what, "has " + std::to_string(control.size()) + " control points");
  if (level < 1) throw InputError(what, "tessellation level must be >= 1");

  const int blocks_x = (width - 1) / 2, blocks_y = (height - 1) / 2;
  const int cols = blocks_x * level + 1, rows = blocks_y * level + 1;
  TriangleMesh mesh;
  mesh.vertices.resize(static_cast<size_t>(cols) * rows);
  auto cp = [&](int r, int c) -> const BspVertex& { return control[r * width + c]; };

  // Vertices on block borders are shared by neighbouring blocks, so evaluating each
  // grid vertex once from the block that owns it gives a crack-free surface.
  for (int r = 0; r < rows; ++r) {
    const int by = std::min(r / level, blocks_y - 1);
    const float v = static_cast<float>(r - by * level) / level;
    const float v0 = (1 - v) * (1 - v), v1 = 2 * v * (1 - v), v2 = v * v;
    for (int c = 0; c < cols; ++c) {
      const int bx = std::min(c / level, blocks_x - 1);
      const float u = static_cast<float>(c - bx * level) / level;
      const float u0 = (1 - u) * (1 - u), u1 = 2 * u * (1 - u), u2 = u * u;
      BspVertex row_blend[3];
      for (int k = 0; k < 3; ++k) {
        const int cr = 2 * by + k, cc = 2 * bx;
        row_blend[k] = blend(cp(cr, cc), cp(cr, cc + 1), cp(cr, cc + 2), u0, u1, u2);
      }
      BspVertex out = blend(row_blend[0], row_blend[1], row_blend[2], v0, v1, v2);
      if (out.normal.squaredNorm() > 0) out.normal.normalize();
      mesh.vertices[r * cols + c] = out;
    }
  }
  for (int r = 0; r + 1 < rows; ++r) {
    for (int c = 0; c + 1 < cols; ++c) {
      const int i00 = r * cols + c, i01 = i00 + 1, i10 = i00 + cols, i11 = i10 + 1;
      mesh.indices.insert(mesh.indices.end(), {i00, i10, i01, i01, i10, i11});
    }
  }
  return mesh;
}

}  // namespace valerant::quake3
