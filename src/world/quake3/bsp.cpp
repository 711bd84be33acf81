#include "valerant/world/quake3/bsp.h"

#include <cstring>
#include <sstream>

#include "valerant/common/error.h"

namespace valerant::quake3 {
namespace {

// Lump order and on-disk record sizes of IBSP version 46 (ioquake3 qfiles.h).
enum Lump {
  kEntities = 0, kShaders, kPlanes, kNodes, kLeafs, kLeafFaces, kLeafBrushes, kModels,
  kBrushes, kBrushSides, kVertices, kMeshVertices, kEffects, kFaces, kLightmaps,
  kLightGrid, kVisibility, kLumpCount
};

class LumpReader {
 public:
  LumpReader(const std::vector<uint8_t>& bytes, const std::string& source)
      : bytes_(bytes), source_(source) {
    if (bytes.size() < 8 + kLumpCount * 8) throw InputError(source, "file too small for a BSP header");
    if (std::memcmp(bytes.data(), "IBSP", 4) != 0) throw InputError(source, "not an IBSP file (bad magic)");
    const int version = readInt(4);
    if (version != 46)
      throw InputError(source, "unsupported BSP version " + std::to_string(version) + " (need 46)");
  }

  // Offset and record count of a lump whose records are `record_size` bytes.
  std::pair<size_t, size_t> lump(Lump l, size_t record_size) const {
    const int64_t offset = readInt(8 + l * 8), length = readInt(12 + l * 8);
    if (offset < 0 || length < 0 || static_cast<uint64_t>(offset + length) > bytes_.size())
      throw InputError(source_, "lump " + std::to_string(l) + " lies outside the file");
    if (record_size > 1 && length % record_size != 0)
      throw InputError(source_, "lump " + std::to_string(l) + " length " + std::to_string(length) +
                                    " is not a multiple of its record size " +
                                    std::to_string(record_size));
    return {static_cast<size_t>(offset), static_cast<size_t>(length) / record_size};
  }

  int32_t readInt(size_t at) const {
    int32_t v;
    std::memcpy(&v, bytes_.data() + at, 4);  // the format is little-endian, like x86
    return v;
  }
  float readFloat(size_t at) const {
    float v;
    std::memcpy(&v, bytes_.data() + at, 4);
    return v;
  }
  Eigen::Vector3f readVec3(size_t at) const {
    return {readFloat(at), readFloat(at + 4), readFloat(at + 8)};
  }
  Eigen::Vector3i readVec3i(size_t at) const { return {readInt(at), readInt(at + 4), readInt(at + 8)}; }
  std::string readString(size_t at, size_t max) const {
    const char* p = reinterpret_cast<const char*>(bytes_.data() + at);
    return std::string(p, strnlen(p, max));
  }
  const uint8_t* data(size_t at) const { return bytes_.data() + at; }

 private:
  const std::vector<uint8_t>& bytes_;
  std::string source_;
};

template <typename T, typename Fn>
std::vector<T> readRecords(const LumpReader& r, Lump l, size_t size, Fn&& parse) {
  auto [offset, count] = r.lump(l, size);
  std::vector<T> out(count);
  for (size_t i = 0; i < count; ++i) out[i] = parse(offset + i * size);
  return out;
}

// The entity lump is a sequence of { "key" "value" ... } blocks.
std::vector<BspEntity> parseEntities(const std::string& text, const std::string& source) {
  std::vector<BspEntity> entities;
  size_t i = 0;
  auto skipSpace = [&] { while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i; };
  auto quoted = [&]() -> std::string {
    skipSpace();
    if (i >= text.size() || text[i] != '"') throw InputError(source, "malformed entity lump near byte " + std::to_string(i));
    const size_t end = text.find('"', i + 1);
    if (end == std::string::npos) throw InputError(source, "unterminated string in entity lump");
    std::string s = text.substr(i + 1, end - i - 1);
    i = end + 1;
    return s;
  };
  while (true) {
    skipSpace();
    if (i >= text.size() || text[i] == '\0') break;
    if (text[i] != '{') throw InputError(source, "malformed entity lump near byte " + std::to_string(i));
    ++i;
    BspEntity entity;
    while (true) {
      skipSpace();
      if (i >= text.size()) throw InputError(source, "unterminated entity in entity lump");
      if (text[i] == '}') { ++i; break; }
      std::string key = quoted();
      entity[key] = quoted();
    }
    entities.push_back(std::move(entity));
  }
  return entities;
}

template <typename T>
void checkRange(int index, int count, const std::vector<T>& target, const std::string& what,
                const std::string& source) {
  if (count < 0 || index < 0 || static_cast<size_t>(index) + count > target.size())
    throw InputError(source, what + " index range [" + std::to_string(index) + ", +" +
                                 std::to_string(count) + ") out of bounds (" +
                                 std::to_string(target.size()) + ")");
}

// The node tree must be a tree: every walk from the root (node 0) reaches a leaf in
// finitely many steps, or leafAt() loops forever. A depth-first walk that meets each
// node once (O(nodes)) rejects a child that leads back to one of its ancestors (a
// cycle) and a node reached a second time from another parent (a shared subtree,
// which a compiled tree never has). Nodes the root never reaches are left alone: no
// lookup visits them. Child indices must already be in range.
void validateNodeTree(const BspMap& m, const std::string& src) {
  enum : uint8_t { kUnseen, kOnPath, kDone };
  std::vector<uint8_t> state(m.nodes.size(), kUnseen);
  std::vector<int> parent(m.nodes.size(), -1);
  struct Frame {
    int node;
    int next_child;
  };
  std::vector<Frame> path{{0, 0}};
  state[0] = kOnPath;
  while (!path.empty()) {
    Frame& top = path.back();
    if (top.next_child == 2) {
      state[top.node] = kDone;
      path.pop_back();
      continue;
    }
    const int side = top.next_child++;
    const int child = m.nodes[top.node].children[side];
    if (child < 0) continue;  // a leaf
    const std::string edge =
        "child " + std::to_string(side) + " of node " + std::to_string(top.node) + " is node " + std::to_string(child);
    if (state[child] == kOnPath)
      throw InputError(src, "BSP node tree has a cycle: " + edge + ", one of its own ancestors" +
                                (child == top.node ? " (itself)" : ""));
    if (state[child] == kDone)
      throw InputError(src, "BSP node tree is not a tree: " + edge + ", already reached from node " +
                                std::to_string(parent[child]));
    state[child] = kOnPath;
    parent[child] = top.node;
    path.push_back({child, 0});  // invalidates `top`
  }
}

void validate(const BspMap& m, const std::string& src) {
  if (m.models.empty()) throw InputError(src, "no world model");
  if (m.nodes.empty() || m.leafs.empty()) throw InputError(src, "no BSP tree (nodes or leafs lump empty)");
  for (const auto& n : m.nodes) {
    checkRange(n.plane, 1, m.planes, "node plane", src);
    for (int c : n.children) {
      if (c >= 0) checkRange(c, 1, m.nodes, "node child", src);
      else checkRange(-(c + 1), 1, m.leafs, "node leaf", src);
    }
  }
  validateNodeTree(m, src);
  for (const auto& l : m.leafs) {
    checkRange(l.first_leaf_face, l.num_leaf_faces, m.leaf_faces, "leaf face", src);
    checkRange(l.first_leaf_brush, l.num_leaf_brushes, m.leaf_brushes, "leaf brush", src);
  }
  for (int f : m.leaf_faces) checkRange(f, 1, m.faces, "leaf face entry", src);
  for (int b : m.leaf_brushes) checkRange(b, 1, m.brushes, "leaf brush entry", src);
  for (const auto& b : m.brushes) {
    checkRange(b.first_side, b.num_sides, m.brush_sides, "brush side", src);
    checkRange(b.shader, 1, m.shaders, "brush shader", src);
  }
  for (const auto& s : m.brush_sides) checkRange(s.plane, 1, m.planes, "brush side plane", src);
  for (const auto& mo : m.models) {
    checkRange(mo.first_face, mo.num_faces, m.faces, "model face", src);
    checkRange(mo.first_brush, mo.num_brushes, m.brushes, "model brush", src);
  }
  for (const auto& f : m.faces) {
    checkRange(f.shader, 1, m.shaders, "face shader", src);
    checkRange(f.first_vertex, f.num_vertices, m.vertices, "face vertex", src);
    checkRange(f.first_mesh_vertex, f.num_mesh_vertices, m.mesh_vertices, "face mesh vertex", src);
    if (f.lightmap >= static_cast<int>(m.lightmaps.size())) throw InputError(src, "face lightmap out of bounds");
    for (int k = 0; k < f.num_mesh_vertices; ++k) {
      const int v = m.mesh_vertices[f.first_mesh_vertex + k];
      if (v < 0 || v >= f.num_vertices) throw InputError(src, "mesh vertex outside its face");
    }
  }
  const auto& vis = m.visibility;
  if (vis.num_clusters > 0 && static_cast<size_t>(vis.num_clusters) * vis.bytes_per_cluster > vis.bits.size())
    throw InputError(src, "visibility lump shorter than its header says");
}

}  // namespace

bool BspVisibility::visible(int from, int to) const {
  if (num_clusters == 0 || from < 0) return true;
  if (to < 0) return false;
  if (from >= num_clusters || to >= num_clusters) return true;
  return bits[static_cast<size_t>(from) * bytes_per_cluster + (to >> 3)] & (1 << (to & 7));
}

std::vector<SpawnPoint> BspMap::spawnPoints() const {
  std::vector<SpawnPoint> out;
  for (const auto& e : entities) {
    auto cls = e.find("classname");
    if (cls == e.end() || (cls->second != "info_player_deathmatch" && cls->second != "info_player_start"))
      continue;
    auto origin = e.find("origin");
    if (origin == e.end()) continue;
    SpawnPoint s;
    s.classname = cls->second;
    std::istringstream in(origin->second);
    if (!(in >> s.origin.x() >> s.origin.y() >> s.origin.z())) continue;
    if (auto angle = e.find("angle"); angle != e.end()) {
      std::istringstream a(angle->second);
      if (!(a >> s.yaw_deg)) s.yaw_deg = 0;  // the game reads a malformed angle as 0 too
    }
    out.push_back(s);
  }
  return out;
}

int bspLeafAt(const std::vector<BspNode>& nodes, const std::vector<BspPlane>& planes, const Eigen::Vector3f& p) {
  int index = 0;
  while (index >= 0) {
    const BspNode& node = nodes[index];
    const BspPlane& plane = planes[node.plane];
    index = node.children[plane.normal.dot(p) - plane.dist >= 0 ? 0 : 1];
  }
  return -(index + 1);
}

int BspMap::leafAt(const Eigen::Vector3f& p) const { return bspLeafAt(nodes, planes, p); }

BspMap parseBsp(const std::vector<uint8_t>& bytes, const std::string& source) {
  LumpReader r(bytes, source);
  BspMap m;
  m.name = source;

  auto [ent_offset, ent_length] = r.lump(kEntities, 1);
  m.entities = parseEntities(
      std::string(reinterpret_cast<const char*>(r.data(ent_offset)), ent_length), source);

  m.shaders = readRecords<BspShader>(r, kShaders, 72, [&](size_t at) {
    return BspShader{r.readString(at, 64), r.readInt(at + 64), r.readInt(at + 68)};
  });
  m.planes = readRecords<BspPlane>(r, kPlanes, 16, [&](size_t at) {
    return BspPlane{r.readVec3(at), r.readFloat(at + 12)};
  });
  m.nodes = readRecords<BspNode>(r, kNodes, 36, [&](size_t at) {
    BspNode n;
    n.plane = r.readInt(at);
    n.children = {r.readInt(at + 4), r.readInt(at + 8)};
    n.mins = r.readVec3i(at + 12);
    n.maxs = r.readVec3i(at + 24);
    return n;
  });
  m.leafs = readRecords<BspLeaf>(r, kLeafs, 48, [&](size_t at) {
    BspLeaf l;
    l.cluster = r.readInt(at);
    l.area = r.readInt(at + 4);
    l.mins = r.readVec3i(at + 8);
    l.maxs = r.readVec3i(at + 20);
    l.first_leaf_face = r.readInt(at + 32);
    l.num_leaf_faces = r.readInt(at + 36);
    l.first_leaf_brush = r.readInt(at + 40);
    l.num_leaf_brushes = r.readInt(at + 44);
    return l;
  });
  m.leaf_faces = readRecords<int>(r, kLeafFaces, 4, [&](size_t at) { return r.readInt(at); });
  m.leaf_brushes = readRecords<int>(r, kLeafBrushes, 4, [&](size_t at) { return r.readInt(at); });
  m.models = readRecords<BspModel>(r, kModels, 40, [&](size_t at) {
    BspModel mo;
    mo.mins = r.readVec3(at);
    mo.maxs = r.readVec3(at + 12);
    mo.first_face = r.readInt(at + 24);
    mo.num_faces = r.readInt(at + 28);
    mo.first_brush = r.readInt(at + 32);
    mo.num_brushes = r.readInt(at + 36);
    return mo;
  });
  m.brushes = readRecords<BspBrush>(r, kBrushes, 12, [&](size_t at) {
    return BspBrush{r.readInt(at), r.readInt(at + 4), r.readInt(at + 8)};
  });
  m.brush_sides = readRecords<BspBrushSide>(r, kBrushSides, 8, [&](size_t at) {
    return BspBrushSide{r.readInt(at), r.readInt(at + 4)};
  });
  m.vertices = readRecords<BspVertex>(r, kVertices, 44, [&](size_t at) {
    BspVertex v;
    v.position = r.readVec3(at);
    v.texcoord = {r.readFloat(at + 12), r.readFloat(at + 16)};
    v.lmcoord = {r.readFloat(at + 20), r.readFloat(at + 24)};
    v.normal = r.readVec3(at + 28);
    std::memcpy(v.color.data(), r.data(at + 40), 4);
    return v;
  });
  m.mesh_vertices = readRecords<int>(r, kMeshVertices, 4, [&](size_t at) { return r.readInt(at); });
  m.faces = readRecords<BspFace>(r, kFaces, 104, [&](size_t at) {
    BspFace f;
    f.shader = r.readInt(at);
    f.effect = r.readInt(at + 4);
    f.type = static_cast<BspFaceType>(r.readInt(at + 8));
    f.first_vertex = r.readInt(at + 12);
    f.num_vertices = r.readInt(at + 16);
    f.first_mesh_vertex = r.readInt(at + 20);
    f.num_mesh_vertices = r.readInt(at + 24);
    f.lightmap = r.readInt(at + 28);
    f.normal = r.readVec3(at + 88);
    f.patch_size = {r.readInt(at + 96), r.readInt(at + 100)};
    return f;
  });
  constexpr size_t kLightmapBytes = BspLightmap::kSize * BspLightmap::kSize * 3;
  m.lightmaps = readRecords<BspLightmap>(r, kLightmaps, kLightmapBytes, [&](size_t at) {
    BspLightmap lm;
    lm.rgb.assign(r.data(at), r.data(at) + kLightmapBytes);
    return lm;
  });
  auto [vis_offset, vis_length] = r.lump(kVisibility, 1);
  if (vis_length >= 8) {
    m.visibility.num_clusters = r.readInt(vis_offset);
    m.visibility.bytes_per_cluster = r.readInt(vis_offset + 4);
    if (m.visibility.num_clusters < 0 || m.visibility.bytes_per_cluster < 0)
      throw InputError(source, "negative visibility sizes");
    m.visibility.bits.assign(r.data(vis_offset + 8), r.data(vis_offset) + vis_length);
  }
  validate(m, source);
  return m;
}

}  // namespace valerant::quake3
