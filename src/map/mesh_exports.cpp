#include "valerant/map/mesh_exports.h"

// Debian's libtinygltf holds the implementation (TINYGLTF_IMPLEMENTATION is defined in
// that library), so this file only uses the declarations.
#include <tiny_gltf.h>

#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

#include "valerant/common/error.h"
#include "valerant/common/output_file.h"

namespace valerant {
namespace {

// Colours of the marker objects (they carry no surface colour of their own).
const std::array<uint8_t, 3> kSpawnColour{40, 110, 255};
const std::array<uint8_t, 3> kPathColour{255, 210, 0};

void requireMesh(const std::string& path, const SurfaceMesh& mesh) {
  if (mesh.triangles.empty()) throw InputError(path, "refusing to write a mesh without triangles");
}

std::string describe(const MapFrame& frame) {
  std::ostringstream s;
  s << "asset frame: metres, Y up, origin at the spawn's feet, spawn looking along -Z; "
    << frame.metres_per_unit << " m per SLAM map unit (" << frame.scale_source << ")";
  return s.str();
}

// Appends `bytes` to the buffer, padded to 4 bytes as glTF requires of every view,
// and returns its buffer view.
int addView(tinygltf::Model& model, const void* bytes, size_t size, int target) {
  auto& data = model.buffers[0].data;
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = data.size();
  view.byteLength = size;
  view.target = target;
  data.resize(data.size() + size);
  std::memcpy(data.data() + view.byteOffset, bytes, size);
  data.resize((data.size() + 3) / 4 * 4, 0);
  model.bufferViews.push_back(view);
  return static_cast<int>(model.bufferViews.size()) - 1;
}

int addAccessor(tinygltf::Model& model, int view, int component, int type, size_t count, bool normalized = false) {
  tinygltf::Accessor a;
  a.bufferView = view;
  a.componentType = component;
  a.type = type;
  a.count = count;
  a.normalized = normalized;
  model.accessors.push_back(a);
  return static_cast<int>(model.accessors.size()) - 1;
}

// A float VEC3 accessor; positions carry the min / max glTF requires of them.
int addVec3(tinygltf::Model& model, const std::vector<Eigen::Vector3f>& values, bool bounds) {
  std::vector<float> flat;
  flat.reserve(values.size() * 3);
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max()), hi = -lo;
  for (const auto& v : values) {
    flat.insert(flat.end(), {v.x(), v.y(), v.z()});
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const int view = addView(model, flat.data(), flat.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
  const int a = addAccessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, values.size());
  if (bounds) {
    model.accessors[a].minValues = {lo.x(), lo.y(), lo.z()};
    model.accessors[a].maxValues = {hi.x(), hi.y(), hi.z()};
  }
  return a;
}

int addMaterial(tinygltf::Model& model, const std::string& name, const std::array<uint8_t, 3>& rgb) {
  tinygltf::Material m;
  m.name = name;
  m.pbrMetallicRoughness.baseColorFactor = {rgb[0] / 255.0, rgb[1] / 255.0, rgb[2] / 255.0, 1.0};
  m.pbrMetallicRoughness.metallicFactor = 0;
  m.pbrMetallicRoughness.roughnessFactor = 1;
  m.doubleSided = true;  // the scan has holes: back faces show through them
  model.materials.push_back(m);
  return static_cast<int>(model.materials.size()) - 1;
}

int addNode(tinygltf::Model& model, const std::string& name, int mesh) {
  tinygltf::Node node;
  node.name = name;
  node.mesh = mesh;
  model.nodes.push_back(node);
  model.scenes[0].nodes.push_back(static_cast<int>(model.nodes.size()) - 1);
  return static_cast<int>(model.nodes.size()) - 1;
}

}  // namespace

void writeMeshObj(const std::string& path, const SurfaceMesh& mesh, const AssetNodes& nodes, const MapFrame& frame,
                  bool overwrite) {
  requireWritable(path, overwrite);
  requireMesh(path, mesh);
  std::ostringstream out;
  out << "# valerant surface mesh; " << describe(frame) << "\n" << std::setprecision(7);
  auto vertex = [&](const Eigen::Vector3f& p, const std::array<uint8_t, 3>& rgb) {
    out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << ' ' << rgb[0] / 255.f << ' ' << rgb[1] / 255.f << ' '
        << rgb[2] / 255.f << '\n';
  };
  out << "o map\n";
  for (size_t i = 0; i < mesh.positions.size(); ++i) vertex(mesh.positions[i], mesh.colours[i]);
  for (const auto& n : mesh.normals) out << "vn " << n.x() << ' ' << n.y() << ' ' << n.z() << '\n';
  for (const auto& t : mesh.triangles)  // OBJ indices are 1-based; vertex i has normal i
    out << "f " << t[0] + 1 << "//" << t[0] + 1 << ' ' << t[1] + 1 << "//" << t[1] + 1 << ' ' << t[2] + 1 << "//"
        << t[2] + 1 << '\n';
  size_t next = mesh.positions.size() + 1;
  out << "o spawn\n";
  vertex(nodes.spawn.translation().cast<float>(), kSpawnColour);
  out << "p " << next++ << '\n';
  if (nodes.path.size() >= 2) {
    out << "o path\n";
    for (const auto& p : nodes.path) vertex(p, kPathColour);
    out << 'l';
    for (size_t i = 0; i < nodes.path.size(); ++i) out << ' ' << next + i;
    out << '\n';
  }
  writeFileAtomically(path, out.str());
}

void writeMeshGlb(const std::string& path, const SurfaceMesh& mesh, const AssetNodes& nodes, const MapFrame& frame,
                  bool overwrite) {
  requireWritable(path, overwrite);
  requireMesh(path, mesh);
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "valerant";
  model.asset.extras = tinygltf::Value(tinygltf::Value::Object{
      {"frame", tinygltf::Value(describe(frame))},
      {"metres_per_map_unit", tinygltf::Value(frame.metres_per_unit)},
      {"scale_source", tinygltf::Value(frame.scale_source)}});
  model.buffers.resize(1);
  model.scenes.resize(1);
  model.scenes[0].name = "valerant map";
  model.defaultScene = 0;

  tinygltf::Primitive surface;
  surface.mode = TINYGLTF_MODE_TRIANGLES;
  surface.material = addMaterial(model, "map", {255, 255, 255});  // vertex colours carry the colour
  surface.attributes["POSITION"] = addVec3(model, mesh.positions, true);
  surface.attributes["NORMAL"] = addVec3(model, mesh.normals, false);
  // RGBA bytes: vertex attributes must be 4-byte aligned, which RGB bytes are not.
  std::vector<uint8_t> rgba;
  rgba.reserve(mesh.colours.size() * 4);
  for (const auto& c : mesh.colours) rgba.insert(rgba.end(), {c[0], c[1], c[2], 255});
  surface.attributes["COLOR_0"] =
      addAccessor(model, addView(model, rgba.data(), rgba.size(), TINYGLTF_TARGET_ARRAY_BUFFER),
                  TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4, mesh.colours.size(), true);
  surface.indices = addAccessor(
      model,
      addView(model, mesh.triangles.data(), mesh.triangles.size() * sizeof(mesh.triangles[0]),
              TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
      TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, mesh.triangles.size() * 3);
  tinygltf::Mesh map_mesh;
  map_mesh.name = "map";
  map_mesh.primitives.push_back(surface);
  model.meshes.push_back(map_mesh);
  addNode(model, "map", 0);

  const int spawn = addNode(model, "spawn", -1);
  const Eigen::Quaterniond q(nodes.spawn.linear());
  const Eigen::Vector3d t = nodes.spawn.translation();
  model.nodes[spawn].translation = {t.x(), t.y(), t.z()};
  model.nodes[spawn].rotation = {q.x(), q.y(), q.z(), q.w()};

  if (nodes.path.size() >= 2) {
    tinygltf::Primitive line;
    line.mode = TINYGLTF_MODE_LINE_STRIP;
    line.material = addMaterial(model, "path", kPathColour);
    line.attributes["POSITION"] = addVec3(model, nodes.path, true);
    tinygltf::Mesh path_mesh;
    path_mesh.name = "path";
    path_mesh.primitives.push_back(line);
    model.meshes.push_back(path_mesh);
    addNode(model, "path", static_cast<int>(model.meshes.size()) - 1);
  }

  tinygltf::TinyGLTF writer;
  writeThroughTemporary(path, "tinygltf's .glb writer", [&](const std::string& temporary) {
    return writer.WriteGltfSceneToFile(&model, temporary, true, true, false, true);
  });
}

}  // namespace valerant
