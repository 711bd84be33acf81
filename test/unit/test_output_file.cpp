// The output layer every writer goes through: whole files or none, checked writes, and
// the fault injection the fault suite (test/faults) relies on.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "valerant/common/error.h"
#include "valerant/common/output_file.h"

using namespace valerant;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("valerant_test_output_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string readAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

size_t entries(const fs::path& dir) {
  return static_cast<size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

// Sets VALERANT_FAIL_WRITES for one scope.
struct FailWrites {
  explicit FailWrites(const char* items) { ::setenv("VALERANT_FAIL_WRITES", items, 1); }
  ~FailWrites() { ::unsetenv("VALERANT_FAIL_WRITES"); }
};

}  // namespace

TEST(OutputFile, WritesReplaceTheWholeFileAndLeaveNoTemporary) {
  const auto dir = scratch("replace");
  const std::string path = (dir / "report.json").string();
  writeFileAtomically(path, "first, longer content\n");
  writeFileAtomically(path, "second\n");
  EXPECT_EQ(readAll(path), "second\n");
  EXPECT_EQ(entries(dir), 1u);
}

TEST(OutputFile, AFailedWriteKeepsTheOldFileAndNamesThePath) {
  const auto dir = scratch("fail");
  const std::string path = (dir / "map.pcd").string();
  writeFileAtomically(path, "old\n");
  {
    FailWrites fail("map.pcd");
    try {
      writeFileAtomically(path, "new\n");
      FAIL() << "the injected failure did not fail the write";
    } catch (const InputError& e) {
      EXPECT_EQ(e.input(), path);
      EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos);
    }
  }
  EXPECT_EQ(readAll(path), "old\n");
  EXPECT_EQ(entries(dir), 1u);
  // A writer through a path (PCL, tinygltf) that fails or throws leaves nothing either.
  EXPECT_THROW(writeThroughTemporary((dir / "a.ply").string(), "test writer", [](const std::string&) { return false; }),
               InputError);
  EXPECT_THROW(writeThroughTemporary((dir / "b.ply").string(), "test writer",
                                     [](const std::string& temporary) -> bool {
                                       std::ofstream(temporary) << "half";
                                       throw std::runtime_error("library failure");
                                     }),
               InputError);
  EXPECT_EQ(entries(dir), 1u);
  // A folder that does not exist is an error naming the file.
  EXPECT_THROW(writeFileAtomically((dir / "missing" / "x.txt").string(), "x"), InputError);
}

TEST(OutputFile, InjectedFailuresMatchWholeTrailingPathComponents) {
  const auto dir = scratch("match");
  FailWrites fail("snapshot/keyframes.pcd,grid.yaml");
  fs::create_directories(dir / "snapshot");
  EXPECT_THROW(writeFileAtomically((dir / "snapshot" / "keyframes.pcd").string(), "x"), InputError);
  EXPECT_NO_THROW(writeFileAtomically((dir / "keyframes.pcd").string(), "x"));      // another folder
  EXPECT_NO_THROW(writeFileAtomically((dir / "oldsnapshot_keyframes.pcd").string(), "x"));
  EXPECT_THROW(writeFileAtomically((dir / "grid.yaml").string(), "x"), InputError);
  EXPECT_NO_THROW(writeFileAtomically((dir / "my_grid.yaml").string(), "x"));      // not a whole name
}

TEST(OutputFile, ImagesAreEncodedByTheirExtension) {
  const auto dir = scratch("image");
  const cv::Mat image(4, 6, CV_8UC3, cv::Scalar(10, 20, 30));
  writeImageAtomically((dir / "a.png").string(), image);
  const std::string png = readAll(dir / "a.png");
  EXPECT_EQ(png.substr(1, 3), "PNG");
  EXPECT_THROW(writeImageAtomically((dir / "a.unknownformat").string(), image), InputError);
  EXPECT_THROW(writeImageAtomically((dir / "b.png").string(), cv::Mat()), InputError);
  EXPECT_EQ(entries(dir), 1u);
}

TEST(OutputFile, AppendOnlyLogWritesWholeLines) {
  const auto dir = scratch("log");
  const std::string path = (dir / "decisions.jsonl").string();
  {
    AppendOnlyLog log(path, false);
    log.writeLine("{\"step\": 1}");
    log.writeLine("{\"step\": 2}");
  }
  {
    AppendOnlyLog log(path, true);  // a resumed run goes on
    log.writeLine("{\"step\": 3}");
  }
  EXPECT_EQ(readAll(path), "{\"step\": 1}\n{\"step\": 2}\n{\"step\": 3}\n");
  {
    AppendOnlyLog log(path, false);  // a new run starts it empty
    log.writeLine("{\"step\": 1}");
  }
  EXPECT_EQ(readAll(path), "{\"step\": 1}\n");
  FailWrites fail("decisions.jsonl");
  EXPECT_THROW(AppendOnlyLog(path, true), InputError);
}
