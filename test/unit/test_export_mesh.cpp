// Surface mesh and its game-engine files: triangulation of a scanned room, the asset
// frame (metres, Y up), and read-back of OBJ with tinyobjloader and of .glb with
// tinygltf, the readers used in the wild.
#include <gtest/gtest.h>
#include <tiny_gltf.h>
#include <tiny_obj_loader.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "valerant/common/error.h"
#include "valerant/map/map_frame.h"
#include "valerant/map/mesh_exports.h"
#include "valerant/map/surface_mesh.h"

using namespace valerant;

namespace {

constexpr double kEye = 1.0;  // camera height over the floor, map units

// A 4 x 4 room scanned from its centre: floor z = 0 and four walls up to z = 2.5, one
// point every 5 cm, camera at (0, 0, kEye).
KeyframeCloud scannedRoom() {
  KeyframeCloud kf;
  kf.camera_to_map = Eigen::Isometry3d::Identity();
  kf.camera_to_map.translation() = Eigen::Vector3d(0, 0, kEye);
  auto add = [&](double x, double y, double z, std::array<uint8_t, 3> rgb) {
    CloudPoint p;
    p.position = Eigen::Vector3d(x, y, z).cast<float>();
    p.rgb = rgb;
    p.confidence = 10;
    kf.points.push_back(p);
  };
  for (int i = 0; i <= 80; ++i) {
    const double s = -2 + 0.05 * i;
    for (int j = 0; j <= 80; ++j) add(s, -2 + 0.05 * j, 0, {200, 100, 50});
    for (int k = 1; k <= 50; ++k) {
      const double z = 0.05 * k;
      add(s, -2, z, {50, 50, 200});
      add(s, 2, z, {50, 50, 200});
      add(-2, s, z, {50, 50, 200});
      add(2, s, z, {50, 50, 200});
    }
  }
  return kf;
}

FloorPlane roomFloor() {
  FloorPlane f;
  f.n = Eigen::Vector3d::UnitZ();
  f.c = Eigen::Vector3d(0, 0, kEye);
  f.reliable = true;
  return f;
}

struct ScannedMesh {
  MapFrame frame;
  SurfaceMesh map_frame_mesh;
  SurfaceMesh asset_mesh;
};

const ScannedMesh& scannedMesh() {
  static const ScannedMesh mesh = [] {
    Config config;
    MapFusion map(config.map, config.collision);
    map.fuse(scannedRoom(), roomFloor());
    const double voxel = config.map.voxel_eye_heights * kEye;
    ScannedMesh m;
    m.frame = mapFrameOf(roomFloor(), Eigen::Vector3d::UnitX(), false, config);
    m.map_frame_mesh = triangulateCloud(map.voxelCloud(voxel), {Eigen::Vector3d(0, 0, kEye)},
                                        meshParams(config.exports, voxel));
    m.asset_mesh = transformMesh(m.map_frame_mesh, m.frame.mapToAsset());
    return m;
  }();
  return mesh;
}

AssetNodes someNodes() {
  AssetNodes nodes;
  nodes.path = {{0, 0, 0}, {0, 0, -1}, {1, 0, -2}};
  return nodes;
}

std::string tempDir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/valerant_export_mesh_" + name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace

TEST(ExportMesh, TriangulatesTheRoomFacingTheCamera) {
  const SurfaceMesh& mesh = scannedMesh().map_frame_mesh;
  ASSERT_GT(mesh.triangles.size(), 10000u);
  ASSERT_EQ(mesh.positions.size(), mesh.normals.size());
  ASSERT_EQ(mesh.positions.size(), mesh.colours.size());
  ASSERT_EQ(mesh.positions.size(), mesh.heights.size());
  const Eigen::Vector3f camera(0, 0, kEye);
  int facing = 0;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3f a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
    const Eigen::Vector3f normal = (b - a).cross(c - a);
    facing += normal.dot(camera - a) > 0;
    EXPECT_LT((b - a).norm(), 8 * Config().map.voxel_eye_heights * kEye + 1e-4);  // no bridging across the room
  }
  EXPECT_EQ(facing, static_cast<int>(mesh.triangles.size()));  // counter-clockwise seen from inside
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    EXPECT_NEAR(mesh.heights[i], mesh.positions[i].z() / kEye, 0.05);  // h carried over per vertex
}

TEST(ExportMesh, ALargeCloudIsMeshedAtACoarserLeaf) {
  // A 1 x 1 square of floor sampled at `leaf`: (1 / leaf)^2 points.
  std::vector<double> asked;
  auto floor_at = [&](double leaf) {
    asked.push_back(leaf);
    std::vector<FusedPoint> points;
    const int n = static_cast<int>(std::lround(1.0 / leaf));
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        FusedPoint p;
        p.position = Eigen::Vector3f((i + 0.5f) / n, 0, (j + 0.5f) / n);
        points.push_back(p);
      }
    return points;
  };
  // Leaf 0.01: 10,000 points. Budget 5,000: 0.0125 gives 80^2 = 6,400, too many;
  // 0.015625 gives 64^2 = 4,096.
  const MeshCloud coarse = meshCloud(floor_at(0.01), 0.01, 5000, floor_at);
  EXPECT_NEAR(coarse.leaf, 0.015625, 1e-15);
  EXPECT_EQ(coarse.points.size(), 4096u);
  ASSERT_EQ(asked.size(), 3u);  // the caller's cloud, then two coarser ones
  EXPECT_NEAR(asked[1], 0.0125, 1e-15);
  EXPECT_NEAR(asked[2], 0.015625, 1e-15);
  // Within the budget: the cloud as it is, nothing recomputed.
  asked.clear();
  const MeshCloud same = meshCloud(floor_at(0.01), 0.01, 10000, floor_at);
  EXPECT_DOUBLE_EQ(same.leaf, 0.01);
  EXPECT_EQ(same.points.size(), 10000u);
  EXPECT_EQ(asked.size(), 1u);
}

TEST(ExportMesh, AssetFrameIsMetresYUp) {
  const ScannedMesh& m = scannedMesh();
  // One map unit is the eye height: 50 / 32 = 1.5625 m.
  EXPECT_DOUBLE_EQ(m.frame.metres_per_unit, 1.5625);
  EXPECT_EQ(m.frame.scale_source, "eye height");
  const Eigen::Affine3d to_asset = m.frame.mapToAsset();
  EXPECT_TRUE((to_asset * Eigen::Vector3d::Zero()).isZero(1e-12));  // the spawn's feet
  EXPECT_TRUE((to_asset * Eigen::Vector3d(0, 0, 1)).isApprox(Eigen::Vector3d(0, 1.5625, 0)));   // up is +Y
  EXPECT_TRUE((to_asset * Eigen::Vector3d(1, 0, 0)).isApprox(Eigen::Vector3d(0, 0, -1.5625)));  // heading is -Z
  EXPECT_TRUE((to_asset * Eigen::Vector3d(0, -1, 0)).isApprox(Eigen::Vector3d(1.5625, 0, 0)));  // right is +X
  float lowest = 1e9, highest = -1e9;
  for (const auto& p : m.asset_mesh.positions) lowest = std::min(lowest, p.y()), highest = std::max(highest, p.y());
  EXPECT_NEAR(lowest, 0.0, 0.05);
  EXPECT_NEAR(highest, 2.5 * 1.5625, 0.1);
  for (const auto& n : m.asset_mesh.normals) EXPECT_NEAR(n.norm(), 1.0, 1e-4);
}

TEST(ExportMesh, CutAboveDropsTheUpperWalls) {
  const SurfaceMesh& mesh = scannedMesh().asset_mesh;
  const SurfaceMesh cut = cutAbove(mesh, 1.0f);
  ASSERT_FALSE(cut.triangles.empty());
  EXPECT_LT(cut.triangles.size(), mesh.triangles.size());
  for (float h : cut.heights) EXPECT_LE(h, 1.0f);
}

TEST(ExportMesh, ObjReadsBackWithTinyObjLoader) {
  const std::string path = tempDir("obj") + "/mesh.obj";
  const ScannedMesh& m = scannedMesh();
  writeMeshObj(path, m.asset_mesh, someNodes(), m.frame, false);
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  ASSERT_TRUE(tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, path.c_str())) << err;
  std::map<std::string, const tinyobj::shape_t*> by_name;
  for (const auto& s : shapes) by_name[s.name] = &s;
  ASSERT_TRUE(by_name.count("map") && by_name.count("spawn") && by_name.count("path"));
  const auto& map = *by_name["map"];
  EXPECT_EQ(map.mesh.num_face_vertices.size(), m.asset_mesh.triangles.size());
  EXPECT_EQ(attrib.vertices.size() / 3, m.asset_mesh.positions.size() + 1 + 3);  // + spawn + path
  EXPECT_EQ(attrib.normals.size() / 3, m.asset_mesh.normals.size());
  // The first triangle's first vertex, position and colour.
  const auto& first = map.mesh.indices[0];
  const uint32_t v = m.asset_mesh.triangles[0][0];
  EXPECT_EQ(first.vertex_index, static_cast<int>(v));
  EXPECT_NEAR(attrib.vertices[3 * v + 1], m.asset_mesh.positions[v].y(), 1e-5);
  EXPECT_NEAR(attrib.colors[3 * v], m.asset_mesh.colours[v][0] / 255.0, 1e-5);
  EXPECT_EQ(by_name["spawn"]->points.indices.size(), 1u);
  EXPECT_EQ(by_name["path"]->lines.num_line_vertices.size(), 1u);
  EXPECT_EQ(by_name["path"]->lines.indices.size(), 3u);
}

TEST(ExportMesh, GlbReadsBackWithTinyGltf) {
  const std::string path = tempDir("glb") + "/mesh.glb";
  const ScannedMesh& m = scannedMesh();
  AssetNodes nodes = someNodes();
  nodes.spawn.translation() = Eigen::Vector3d(1, 0, 2);
  writeMeshGlb(path, m.asset_mesh, nodes, m.frame, false);
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, path)) << err;
  EXPECT_EQ(model.asset.version, "2.0");
  EXPECT_DOUBLE_EQ(model.asset.extras.Get("metres_per_map_unit").GetNumberAsDouble(), 1.5625);
  std::map<std::string, const tinygltf::Node*> by_name;
  for (const auto& n : model.nodes) by_name[n.name] = &n;
  ASSERT_TRUE(by_name.count("map") && by_name.count("spawn") && by_name.count("path"));
  EXPECT_EQ(by_name["spawn"]->translation, (std::vector<double>{1, 0, 2}));

  const tinygltf::Primitive& surface = model.meshes.at(by_name["map"]->mesh).primitives.at(0);
  EXPECT_EQ(surface.mode, TINYGLTF_MODE_TRIANGLES);
  const auto& positions = model.accessors.at(surface.attributes.at("POSITION"));
  EXPECT_EQ(positions.count, m.asset_mesh.positions.size());
  ASSERT_EQ(positions.minValues.size(), 3u);  // required by glTF for POSITION
  EXPECT_NEAR(positions.minValues[1], 0.0, 0.05);
  const auto& colours = model.accessors.at(surface.attributes.at("COLOR_0"));
  EXPECT_TRUE(colours.normalized);
  EXPECT_EQ(model.accessors.at(surface.indices).count, 3 * m.asset_mesh.triangles.size());
  // The bytes of the first vertex position and its index read back exactly.
  const auto& view = model.bufferViews.at(positions.bufferView);
  const float* xyz = reinterpret_cast<const float*>(model.buffers[0].data.data() + view.byteOffset);
  EXPECT_FLOAT_EQ(xyz[1], m.asset_mesh.positions[0].y());
  const auto& index_view = model.bufferViews.at(model.accessors.at(surface.indices).bufferView);
  const uint32_t* index = reinterpret_cast<const uint32_t*>(model.buffers[0].data.data() + index_view.byteOffset);
  EXPECT_EQ(index[0], m.asset_mesh.triangles[0][0]);

  const tinygltf::Primitive& line = model.meshes.at(by_name["path"]->mesh).primitives.at(0);
  EXPECT_EQ(line.mode, TINYGLTF_MODE_LINE_STRIP);
  EXPECT_EQ(model.accessors.at(line.attributes.at("POSITION")).count, 3u);
}

TEST(ExportMesh, NeverOverwritesAndRefusesEmptyMeshes) {
  const std::string dir = tempDir("overwrite");
  const ScannedMesh& m = scannedMesh();
  writeMeshGlb(dir + "/mesh.glb", m.asset_mesh, someNodes(), m.frame, false);
  writeMeshObj(dir + "/mesh.obj", m.asset_mesh, someNodes(), m.frame, false);
  const auto glb_size = std::filesystem::file_size(dir + "/mesh.glb");
  EXPECT_THROW(writeMeshGlb(dir + "/mesh.glb", cutAbove(m.asset_mesh, 0.5f), someNodes(), m.frame, false), InputError);
  EXPECT_THROW(writeMeshObj(dir + "/mesh.obj", m.asset_mesh, someNodes(), m.frame, false), InputError);
  EXPECT_EQ(std::filesystem::file_size(dir + "/mesh.glb"), glb_size);
  EXPECT_NO_THROW(writeMeshGlb(dir + "/mesh.glb", m.asset_mesh, someNodes(), m.frame, true));
  EXPECT_THROW(writeMeshObj(dir + "/empty.obj", SurfaceMesh{}, someNodes(), m.frame, false), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir + "/empty.obj"));
}
