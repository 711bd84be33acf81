// Pk3 file system: reads real OpenArena archives, overrides like the game, and names
// a broken archive instead of crashing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "openarena_data.h"
#include "valerant/common/error.h"
#include "valerant/world/quake3/pk3_archive.h"

using namespace valerant;
using namespace valerant::quake3;

TEST(Pk3Archive, ReadsAMapFromTheInstalledData) {
  VALERANT_REQUIRE_OPENARENA();
  Pk3FileSystem fs;
  fs.mountDirectory(Pk3FileSystem::defaultDataDir());
  EXPECT_GE(fs.archiveCount(), 5u);
  const auto bytes = fs.read("MAPS/OA_DM1.BSP");  // case-insensitive like the game
  ASSERT_TRUE(bytes.has_value());
  EXPECT_EQ(bytes->size(), 1404976u);  // size listed by `unzip -l pak1-maps.pk3`
  EXPECT_EQ(std::string(bytes->begin(), bytes->begin() + 4), "IBSP");
  EXPECT_FALSE(fs.read("maps/no_such_map.bsp").has_value());
  const auto shaders = fs.list("scripts/", ".shader");
  EXPECT_GT(shaders.size(), 10u);
}

TEST(Pk3Archive, LaterArchivesOverrideEarlierOnes) {
  VALERANT_REQUIRE_OPENARENA();
  Pk3FileSystem fs;
  fs.mountDirectory(Pk3FileSystem::defaultDataDir());
  // aggressor.bsp is in pak1-maps.pk3 and again, newer, in pak6-patch088.pk3.
  EXPECT_NE(fs.archiveOf("maps/aggressor.bsp").find("pak6-patch088.pk3"), std::string::npos);
  EXPECT_EQ(fs.read("maps/aggressor.bsp")->size(), 777072u);
}

TEST(Pk3Archive, CorruptArchiveIsNamed) {
  const std::string path = ::testing::TempDir() + "/corrupt.pk3";
  {
    std::ofstream out(path, std::ios::binary);
    out << "PK\x03\x04 this is not really a zip archive";
  }
  Pk3FileSystem fs;
  try {
    fs.mountArchive(path);
    FAIL() << "a corrupt pk3 was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.input(), path);
  }
}

TEST(Pk3Archive, MissingArchiveAndFolderAreNamed) {
  Pk3FileSystem fs;
  EXPECT_THROW(fs.mountArchive("/nonexistent/x.pk3"), InputError);
  EXPECT_THROW(fs.mountDirectory("/nonexistent/baseoa"), InputError);
}
