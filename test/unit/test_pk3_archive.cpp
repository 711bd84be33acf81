// Pk3 file system: reads real OpenArena archives, overrides like the game, and names
// a broken archive instead of crashing.
#include <gtest/gtest.h>
#include <zip.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

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

namespace {

std::vector<uint8_t> fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// A pk3 holding "maps/check.txt" = "123456789", stored uncompressed, written with libzip.
void writeStoredPk3(const std::string& path) {
  static const char kData[] = "123456789";
  int error = 0;
  zip_t* zip = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &error);
  ASSERT_NE(zip, nullptr) << "libzip error " << error;
  zip_source_t* source = zip_source_buffer(zip, kData, 9, 0);
  ASSERT_NE(source, nullptr);
  const zip_int64_t index = zip_file_add(zip, "maps/check.txt", source, ZIP_FL_ENC_UTF_8);
  ASSERT_GE(index, 0) << zip_strerror(zip);
  ASSERT_EQ(zip_set_file_compression(zip, index, ZIP_CM_STORE, 0), 0);
  ASSERT_EQ(zip_close(zip), 0);
}

}  // namespace

// The stored data of "123456789" (CRC-32 0xcbf43926, the standard check value) with
// one byte changed, its recorded CRC and sizes untouched: the read must fail, naming
// the archive and the entry, instead of returning the damaged bytes.
TEST(Pk3Archive, EntryWithABadCrcIsRejected) {
  const std::string good = ::testing::TempDir() + "/crc_good.pk3", bad = ::testing::TempDir() + "/crc_bad.pk3";
  writeStoredPk3(good);
  std::vector<uint8_t> bytes = fileBytes(good);
  const std::string payload = "123456789";
  const auto at = std::search(bytes.begin(), bytes.end(), payload.begin(), payload.end());
  ASSERT_NE(at, bytes.end()) << "the stored data is not in the file";
  ASSERT_EQ(std::search(at + 1, bytes.end(), payload.begin(), payload.end()), bytes.end());
  at[4] = '6';  // "123466789"
  std::ofstream(bad, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), bytes.size());

  Pk3FileSystem fs_good;
  fs_good.mountArchive(good);
  const auto read = fs_good.read("MAPS/CHECK.TXT");
  ASSERT_TRUE(read.has_value());
  EXPECT_EQ(std::string(read->begin(), read->end()), payload);

  Pk3FileSystem fs_bad;
  fs_bad.mountArchive(bad);  // the directory is intact: only the entry's data is damaged
  EXPECT_TRUE(fs_bad.exists("maps/check.txt"));
  try {
    fs_bad.read("maps/check.txt");
    FAIL() << "an entry with a bad CRC was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.input(), bad + ":maps/check.txt");
    EXPECT_NE(std::string(e.what()).find("CRC-32 mismatch"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("0xcbf43926"), std::string::npos) << e.what();
  }
}
