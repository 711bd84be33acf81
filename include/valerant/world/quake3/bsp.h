#pragma once
// Quake III BSP (IBSP version 46) as stored in a map's .bsp file: every lump the
// renderer, the kinematics and the ground truth use. Coordinates are the game's:
// Z up, game units (32 units = 1 m). Reference: the lump layout of ioquake3's
// qfiles.h; field names follow it where they are not obviously better spelled out.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace valerant::quake3 {

// Surface and content flags of the game (surfaceflags.h) that we act on.
constexpr int kContentsSolid = 0x1;
constexpr int kContentsPlayerClip = 0x10000;
constexpr int kSurfNoDraw = 0x80;
constexpr int kSurfSky = 0x4;
constexpr int kSurfNonSolid = 0x4000;

struct BspShader {
  std::string name;  // e.g. "textures/base_wall/concrete"
  int surface_flags = 0;
  int contents = 0;
};

struct BspPlane {
  Eigen::Vector3f normal;
  float dist = 0;  // points p on the plane satisfy normal.dot(p) == dist
};

struct BspNode {
  int plane = 0;
  std::array<int, 2> children{};  // >= 0: node index; < 0: leaf index -(c+1)
  Eigen::Vector3i mins, maxs;
};

struct BspLeaf {
  int cluster = -1;  // -1: outside the map (never visible)
  int area = 0;
  Eigen::Vector3i mins, maxs;
  int first_leaf_face = 0, num_leaf_faces = 0;
  int first_leaf_brush = 0, num_leaf_brushes = 0;
};

struct BspModel {
  Eigen::Vector3f mins, maxs;
  int first_face = 0, num_faces = 0;
  int first_brush = 0, num_brushes = 0;
};

struct BspBrush {
  int first_side = 0, num_sides = 0;
  int shader = 0;
};

struct BspBrushSide {
  int plane = 0;
  int shader = 0;
};

struct BspVertex {
  Eigen::Vector3f position;
  Eigen::Vector2f texcoord;   // diffuse texture
  Eigen::Vector2f lmcoord;    // lightmap
  Eigen::Vector3f normal;
  std::array<uint8_t, 4> color{};
};

enum class BspFaceType : int { kPolygon = 1, kPatch = 2, kMesh = 3, kBillboard = 4 };

struct BspFace {
  int shader = 0;
  int effect = -1;
  BspFaceType type = BspFaceType::kPolygon;
  int first_vertex = 0, num_vertices = 0;
  int first_mesh_vertex = 0, num_mesh_vertices = 0;
  int lightmap = -1;  // -1: no lightmap (vertex colours light it)
  Eigen::Vector3f normal;
  std::array<int, 2> patch_size{};  // control points per direction for patches
};

struct BspLightmap {
  static constexpr int kSize = 128;
  std::vector<uint8_t> rgb;  // kSize * kSize * 3, row-major as stored
};

// Potentially visible set: clusters x bytes_per_cluster bit rows.
struct BspVisibility {
  int num_clusters = 0;
  int bytes_per_cluster = 0;
  std::vector<uint8_t> bits;
  // True when `to` may be seen from `from`; everything is visible without vis data.
  bool visible(int from, int to) const;
};

// One entity of the entity lump: its key/value pairs.
using BspEntity = std::map<std::string, std::string>;

struct SpawnPoint {
  Eigen::Vector3f origin;  // player origin (24 units above the floor it stands on)
  float yaw_deg = 0;       // "angle" key: 0 looks along +X, 90 along +Y
  std::string classname;
};

struct BspMap {
  std::string name;  // e.g. "oa_dm1"
  std::vector<BspEntity> entities;
  std::vector<BspShader> shaders;
  std::vector<BspPlane> planes;
  std::vector<BspNode> nodes;
  std::vector<BspLeaf> leafs;
  std::vector<int> leaf_faces;
  std::vector<int> leaf_brushes;
  std::vector<BspModel> models;
  std::vector<BspBrush> brushes;
  std::vector<BspBrushSide> brush_sides;
  std::vector<BspVertex> vertices;
  std::vector<int> mesh_vertices;
  std::vector<BspFace> faces;
  std::vector<BspLightmap> lightmaps;
  BspVisibility visibility;

  // info_player_deathmatch and info_player_start entities, in entity-lump order.
  std::vector<SpawnPoint> spawnPoints() const;
  // Index of the leaf containing `p` (world model BSP tree).
  int leafAt(const Eigen::Vector3f& p) const;
};

// Index of the leaf containing `p` in the node tree `nodes` (root: node 0) over
// `planes`; the tree must be one parseBsp accepted.
int bspLeafAt(const std::vector<BspNode>& nodes, const std::vector<BspPlane>& planes, const Eigen::Vector3f& p);

// Parses a whole .bsp file image. `source` names it in errors. Throws InputError on
// a wrong magic/version, a lump outside the file, inconsistent indices, or a node tree
// that is no tree (a cycle, or a node reached from two parents), where leafAt() would
// never reach a leaf.
BspMap parseBsp(const std::vector<uint8_t>& bytes, const std::string& source);

}  // namespace valerant::quake3
