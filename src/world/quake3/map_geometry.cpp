#include "valerant/world/quake3/map_geometry.h"

#include "valerant/world/quake3/patch.h"

namespace valerant::quake3 {
namespace {

constexpr int kContentsFog = 0x40;  // fog volumes are drawn as a screen effect, not geometry

bool isDrawn(const BspFace& face, const BspShader& shader) {
  if (shader.surface_flags & kSurfNoDraw) return false;
  if (shader.contents & kContentsFog) return false;
  return face.type == BspFaceType::kPolygon || face.type == BspFaceType::kMesh ||
         face.type == BspFaceType::kPatch;
}

}  // namespace

MapGeometry buildMapGeometry(const BspMap& map, int patch_level) {
  MapGeometry g;
  // BSP vertices keep their indices; patch vertices are appended after them.
  g.vertices = map.vertices;
  g.surfaces.resize(map.faces.size());
  for (size_t i = 0; i < map.faces.size(); ++i) {
    const BspFace& face = map.faces[i];
    const BspShader& shader = map.shaders[face.shader];
    DrawSurface& s = g.surfaces[i];
    s.shader = face.shader;
    s.lightmap = face.lightmap;
    s.sky = (shader.surface_flags & kSurfSky) != 0;
    s.first_index = static_cast<uint32_t>(g.indices.size());
    if (!isDrawn(face, shader)) continue;
    if (face.type == BspFaceType::kPatch) {
      std::vector<BspVertex> control(map.vertices.begin() + face.first_vertex,
                                     map.vertices.begin() + face.first_vertex + face.num_vertices);
      const TriangleMesh mesh =
          tessellatePatch(control, face.patch_size[0], face.patch_size[1], patch_level);
      const auto base = static_cast<uint32_t>(g.vertices.size());
      g.vertices.insert(g.vertices.end(), mesh.vertices.begin(), mesh.vertices.end());
      for (int idx : mesh.indices) g.indices.push_back(base + idx);
    } else {
      for (int k = 0; k < face.num_mesh_vertices; ++k)
        g.indices.push_back(face.first_vertex + map.mesh_vertices[face.first_mesh_vertex + k]);
    }
    s.num_indices = static_cast<uint32_t>(g.indices.size()) - s.first_index;
    for (uint32_t k = s.first_index; k < s.first_index + s.num_indices; ++k)
      s.bounds.extend(g.vertices[g.indices[k]].position);
    if (!s.sky) g.bounds.extend(s.bounds);
  }
  return g;
}

}  // namespace valerant::quake3
