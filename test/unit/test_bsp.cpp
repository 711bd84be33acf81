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
