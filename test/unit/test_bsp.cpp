// BSP parsing: lump counts of a real map (checked against the file header with an
// independent script), spawn points, PVS, and clear errors for damaged files.
#include <gtest/gtest.h>

#include <cstring>

#include "openarena_data.h"
#include "valerant/common/error.h"
#include "valerant/world/quake3/bsp.h"
#include "valerant/world/quake3/pk3_archive.h"

using namespace valerant;
using namespace valerant::quake3;

namespace {

std::vector<uint8_t> readOaDm1() {
  Pk3FileSystem fs;
  fs.mountDirectory(Pk3FileSystem::defaultDataDir());
  return *fs.read("maps/oa_dm1.bsp");
}

}  // namespace

TEST(Bsp, LumpCountsOfOaDm1) {
  VALERANT_REQUIRE_OPENARENA();
  const BspMap m = parseBsp(readOaDm1(), "oa_dm1");
  // Record counts = lump length / record size, read from the header by hand.
  EXPECT_EQ(m.shaders.size(), 44u);
  EXPECT_EQ(m.planes.size(), 1082u);
  EXPECT_EQ(m.nodes.size(), 1113u);
  EXPECT_EQ(m.leafs.size(), 1123u);
  EXPECT_EQ(m.leaf_faces.size(), 4103u);
  EXPECT_EQ(m.leaf_brushes.size(), 1929u);
  EXPECT_EQ(m.models.size(), 9u);
  EXPECT_EQ(m.brushes.size(), 575u);
  EXPECT_EQ(m.brush_sides.size(), 3641u);
  EXPECT_EQ(m.vertices.size(), 8284u);
  EXPECT_EQ(m.mesh_vertices.size(), 7842u);
  EXPECT_EQ(m.faces.size(), 902u);
  EXPECT_EQ(m.lightmaps.size(), 14u);
  EXPECT_GT(m.visibility.num_clusters, 0);
  EXPECT_EQ(m.spawnPoints().size(), 8u);  // 7 info_player_deathmatch + 1 info_player_start
}

TEST(Bsp, PatchFacesOfOaDm5) {
  VALERANT_REQUIRE_OPENARENA();
  Pk3FileSystem fs;
  fs.mountDirectory(Pk3FileSystem::defaultDataDir());
  const BspMap m = parseBsp(*fs.read("maps/oa_dm5.bsp"), "oa_dm5");
  size_t patches = 0;
  for (const auto& f : m.faces) {
    if (f.type != BspFaceType::kPatch) continue;
    ++patches;
    EXPECT_EQ(f.patch_size[0] % 2, 1);  // odd control grids, as tessellation needs
    EXPECT_EQ(f.num_vertices, f.patch_size[0] * f.patch_size[1]);
  }
  EXPECT_EQ(m.faces.size(), 2213u);
  EXPECT_EQ(patches, 124u);  // face type 2, counted by hand from the face lump
}

TEST(Bsp, SpawnLeafSeesItself) {
  VALERANT_REQUIRE_OPENARENA();
  const BspMap m = parseBsp(readOaDm1(), "oa_dm1");
  for (const auto& s : m.spawnPoints()) {
    const int leaf = m.leafAt(s.origin);
    ASSERT_GE(leaf, 0);
    const int cluster = m.leafs[leaf].cluster;
    EXPECT_GE(cluster, 0) << "spawn outside the map";
    EXPECT_TRUE(m.visibility.visible(cluster, cluster));
  }
}

TEST(Bsp, DamagedFilesAreRejectedWithTheirName) {
  VALERANT_REQUIRE_OPENARENA();
  const std::vector<uint8_t> good = readOaDm1();
  auto expectError = [](const std::vector<uint8_t>& bytes, const std::string& fragment) {
    try {
      parseBsp(bytes, "damaged.bsp");
      ADD_FAILURE() << "accepted a damaged file, expected: " << fragment;
    } catch (const InputError& e) {
      EXPECT_EQ(e.input(), "damaged.bsp");
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  std::vector<uint8_t> bad = good;
  bad[0] = 'X';
  expectError(bad, "bad magic");
  bad = good;
  bad[4] = 47;
  expectError(bad, "version 47");
  bad = std::vector<uint8_t>(good.begin(), good.begin() + good.size() / 2);
  expectError(bad, "outside the file");
  expectError(std::vector<uint8_t>(good.begin(), good.begin() + 20), "too small");
  bad = good;
  // Point the first face's shader far outside the shader lump.
  int32_t faces_offset;
  std::memcpy(&faces_offset, good.data() + 8 + 13 * 8, 4);
  const int32_t huge = 1 << 20;
  std::memcpy(bad.data() + faces_offset, &huge, 4);
  expectError(bad, "face shader");
}

namespace {

// A minimal IBSP 46 image built by hand: planes x = 0 and y = 0, the given nodes
// (children as stored: >= 0 a node, < 0 the leaf -(c+1)), `leafs` leaves with clusters
// 0, 1, ... and a world model; every other lump empty.
std::vector<uint8_t> handMadeBsp(const std::vector<std::array<int, 2>>& node_children, int leafs) {
  constexpr int kLumps = 17;
  std::vector<std::vector<int32_t>> lumps(kLumps);  // every record here is 4-byte words
  auto f = [](float v) {
    int32_t i;
    std::memcpy(&i, &v, 4);
    return i;
  };
  lumps[2] = {f(1), f(0), f(0), f(0), f(0), f(1), f(0), f(0)};  // planes: normal, dist
  for (size_t n = 0; n < node_children.size(); ++n) {
    const int32_t plane = static_cast<int32_t>(n % 2);  // alternate x = 0 and y = 0
    lumps[3].insert(lumps[3].end(), {plane, node_children[n][0], node_children[n][1], -64, -64, -64, 64, 64, 64});
  }
  for (int l = 0; l < leafs; ++l)  // cluster, area, mins, maxs, leaf faces, leaf brushes
    lumps[4].insert(lumps[4].end(), {l, 0, -64, -64, -64, 64, 64, 64, 0, 0, 0, 0});
  lumps[7] = {f(-64), f(-64), f(-64), f(64), f(64), f(64), 0, 0, 0, 0};  // world model
  std::vector<uint8_t> bytes(8 + kLumps * 8);
  std::memcpy(bytes.data(), "IBSP", 4);
  const int32_t version = 46;
  std::memcpy(bytes.data() + 4, &version, 4);
  for (int l = 0; l < kLumps; ++l) {
    const int32_t offset = static_cast<int32_t>(bytes.size()), length = static_cast<int32_t>(lumps[l].size() * 4);
    std::memcpy(bytes.data() + 8 + l * 8, &offset, 4);
    std::memcpy(bytes.data() + 12 + l * 8, &length, 4);
    bytes.resize(bytes.size() + length);
    std::memcpy(bytes.data() + offset, lumps[l].data(), length);
  }
  return bytes;
}

// parseBsp must throw an InputError naming the file whose message holds `fragment`.
void expectTreeRejected(const std::vector<std::array<int, 2>>& nodes, int leafs, const std::string& fragment) {
  try {
    parseBsp(handMadeBsp(nodes, leafs), "cyclic.bsp");
    ADD_FAILURE() << "accepted a node tree that is no tree, expected: " << fragment;
  } catch (const InputError& e) {
    EXPECT_EQ(e.input(), "cyclic.bsp");
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

}  // namespace

// Node 0 splits at x = 0 (x >= 0: node 1, else leaf 0); node 1 splits at y = 0
// (y >= 0: leaf 1, else leaf 2). Each point's leaf follows by hand.
TEST(Bsp, HandMadeTreeLoadsAndLocatesPoints) {
  const BspMap m = parseBsp(handMadeBsp({{1, -1}, {-2, -3}}, 3), "tree.bsp");
  ASSERT_EQ(m.nodes.size(), 2u);
  ASSERT_EQ(m.leafs.size(), 3u);
  EXPECT_EQ(m.leafAt({-5, 3, 0}), 0);
  EXPECT_EQ(m.leafAt({5, 3, 0}), 1);
  EXPECT_EQ(m.leafAt({5, -3, 0}), 2);
  EXPECT_EQ(m.leafAt({0, 0, 0}), 1);  // on a plane: the front side, like the game
  EXPECT_EQ(m.leafs[m.leafAt({5, -3, 0})].cluster, 2);
}

// Trees whose lookups would never reach a leaf (leafAt would loop forever) or that
// share a subtree are rejected at load, naming the file and the node.
TEST(Bsp, NodeTreeWithACycleIsRejected) {
  // Node 1's back child leads back to the root: (5, -3, 0) would loop 0 -> 1 -> 0 ...
  expectTreeRejected({{1, -1}, {-2, 0}}, 3, "cycle: child 1 of node 1 is node 0, one of its own ancestors");
  // Node 1 is its own front child.
  expectTreeRejected({{1, -1}, {1, -3}}, 3, "cycle: child 0 of node 1 is node 1, one of its own ancestors (itself)");
  // The root is its own child.
  expectTreeRejected({{0, -1}}, 1, "cycle: child 0 of node 0 is node 0");
  // A longer loop: 0 -> 1 -> 2 -> 3 -> 1.
  expectTreeRejected({{1, -1}, {2, -2}, {-3, 3}, {1, -4}}, 4, "cycle: child 0 of node 3 is node 1");
  // Both children of the root are node 1: no loop, but node 1 is reached twice.
  expectTreeRejected({{1, 1}, {-1, -2}}, 2, "not a tree: child 1 of node 0 is node 1, already reached from node 0");
}
