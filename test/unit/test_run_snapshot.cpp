// The snapshot of a run's committed steps (run_snapshot.h): a run directory of its own
// that loadRunMap reads back whole, written in parts so that a write costs what the map
// gained since the last one: parts that still hold are linked, not written again, and a
// rewind or a loop closure rewrites only what it changed.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>

#include "valerant/common/error.h"
#include "valerant/map/run_snapshot.h"

using namespace valerant;
namespace fs = std::filesystem;

namespace {

// A keyframe at (x, 0, 0) with `n` points at (x, i, 0), i = 0 .. n-1, and a fresh id.
std::shared_ptr<const FusedKeyframe> keyframeAt(double x, int n) {
  auto kf = std::make_shared<FusedKeyframe>();
  kf->id = newKeyframeId();
  kf->camera_to_map = Eigen::Isometry3d::Identity();
  kf->camera_to_map.translation() = Eigen::Vector3d(x, 0, 0);
  for (int i = 0; i < n; ++i) {
    FusedPoint p;
    p.position = Eigen::Vector3f(static_cast<float>(x), static_cast<float>(i), 0);
    p.rgb = {10, 20, 30};
    p.confidence = 5;
    p.h = 0.25f * static_cast<float>(i);
    kf->points.push_back(p);
  }
  return kf;
}

RunMap emptyRun() {
  const Config config = loadConfig(defaultConfigPath());
  Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();
  FloorPlane floor;
  floor.n = Eigen::Vector3d::UnitZ();
  floor.c = Eigen::Vector3d(0, 0, 0.5);
  floor.reliable = true;
  return RunMap{config, MapFusion(config.map, config.collision),
                mapFrameOf(floor, Eigen::Vector3d::UnitX(), false, config), {camera}, nlohmann::json::object()};
}

std::string runDir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/valerant_run_snapshot_" + name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  saveRunConfig(dir, ConfigDocument::load(defaultConfigPath()), false);
  return dir;
}

nlohmann::json snapshotReport(const std::string& dir) {
  std::ifstream in(runSnapshotDir(dir) + "/report.json");
  return nlohmann::json::parse(in);
}

// The point files of the snapshot, as its report lists them.
std::vector<std::string> partFiles(const std::string& dir) {
  const nlohmann::json report = snapshotReport(dir);
  std::vector<std::string> files;
  for (const auto& part : report["run_map"]["point_files"]) files.push_back(part["file"]);
  return files;
}

ino_t inode(const std::string& path) {
  struct stat s {};
  EXPECT_EQ(::stat(path.c_str(), &s), 0) << path;
  return s.st_ino;
}

// Every keyframe of `loaded` has the pose and points of the same keyframe of `run`.
void expectSameMap(const RunMap& loaded, const RunMap& run) {
  const auto& a = loaded.map.keyframes();
  const auto& b = run.map.keyframes();
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_TRUE(a[k]->camera_to_map.isApprox(b[k]->camera_to_map)) << k;
    ASSERT_EQ(a[k]->points.size(), b[k]->points.size()) << k;
    for (size_t i = 0; i < a[k]->points.size(); ++i) {
      EXPECT_EQ(a[k]->points[i].position, b[k]->points[i].position);
      EXPECT_EQ(a[k]->points[i].h, b[k]->points[i].h);
    }
  }
}

}  // namespace

TEST(RunSnapshot, IsARunDirectoryOfItsOwnThatReadsBackWhole) {
  const std::string dir = runDir("whole");
  RunMap run = emptyRun();
  for (int k = 0; k < 3; ++k) run.map.add(keyframeAt(k, 4 + k));
  RunSnapshot snapshot(dir);
  snapshot.write(run, {{"tool", "valerant_explore"}, {"steps", 1}});
  EXPECT_FALSE(fs::exists(dir + "/.snapshot.partial"));
  const RunMap loaded = loadRunMap(runSnapshotDir(dir));
  EXPECT_EQ(loaded.report["steps"], 1);
  EXPECT_EQ(loaded.report["run_map"]["points"], 4 + 5 + 6);
  EXPECT_EQ(loaded.trajectory.size(), 1u);
  expectSameMap(loaded, run);
  // The run itself has no report yet: loading it points at the snapshot.
  try {
    loadRunMap(dir);
    ADD_FAILURE() << "an unfinished run loaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the map of its committed steps is in " + runSnapshotDir(dir)),
              std::string::npos);
  }
}

TEST(RunSnapshot, AWriteLinksThePartsThatHoldAndWritesOnlyTheNewKeyframes) {
  const std::string dir = runDir("append");
  RunMap run = emptyRun();
  run.map.add(keyframeAt(0, 3));
  run.map.add(keyframeAt(1, 3));
  RunSnapshot snapshot(dir);
  snapshot.write(run, {{"steps", 1}});
  ASSERT_EQ(partFiles(dir), std::vector<std::string>{"keyframes.000000.pcd"});
  const ino_t first = inode(runSnapshotDir(dir) + "/keyframes.000000.pcd");
  run.map.add(keyframeAt(2, 7));
  snapshot.write(run, {{"steps", 2}});
  // The first part is the same file (linked into the new snapshot); the second holds the
  // new keyframe's 7 points alone.
  ASSERT_EQ(partFiles(dir), (std::vector<std::string>{"keyframes.000000.pcd", "keyframes.000001.pcd"}));
  EXPECT_EQ(inode(runSnapshotDir(dir) + "/keyframes.000000.pcd"), first);
  EXPECT_EQ(snapshotReport(dir)["run_map"]["point_files"][1]["points"], 7);
  expectSameMap(loadRunMap(runSnapshotDir(dir)), run);
  // A step that added nothing writes no part.
  snapshot.write(run, {{"steps", 3}});
  EXPECT_EQ(partFiles(dir).size(), 2u);
}

TEST(RunSnapshot, ARewindRewritesThePartItCutAndKeepsTheOnesBefore) {
  const std::string dir = runDir("rewind");
  RunMap run = emptyRun();
  RunSnapshot snapshot(dir);
  run.map.add(keyframeAt(0, 2));
  snapshot.write(run, {{"steps", 1}});  // part 0: keyframe 0
  run.map.add(keyframeAt(1, 2));
  run.map.add(keyframeAt(2, 2));
  snapshot.write(run, {{"steps", 2}});  // part 1: keyframes 1, 2
  run.map.truncate(2);                  // the rewind cuts part 1 after keyframe 1
  run.map.add(keyframeAt(5, 3));
  snapshot.write(run, {{"steps", 3}});
  // Part 0 holds; keyframe 1 and the new keyframe go to part 2 (2 + 3 points).
  ASSERT_EQ(partFiles(dir), (std::vector<std::string>{"keyframes.000000.pcd", "keyframes.000002.pcd"}));
  EXPECT_EQ(snapshotReport(dir)["run_map"]["point_files"][1]["points"], 5);
  EXPECT_FALSE(fs::exists(runSnapshotDir(dir) + "/keyframes.000001.pcd"));
  expectSameMap(loadRunMap(runSnapshotDir(dir)), run);
}

TEST(RunSnapshot, CorrectedKeyframesAreWrittenAgain) {
  const std::string dir = runDir("closure");
  RunMap run = emptyRun();
  RunSnapshot snapshot(dir);
  run.map.add(keyframeAt(0, 2));
  run.map.add(keyframeAt(1, 2));
  snapshot.write(run, {{"steps", 1}});
  // A loop closure replaces every keyframe by a corrected copy with a new id.
  run.map.truncate(0);
  run.map.add(keyframeAt(0.5, 2));
  run.map.add(keyframeAt(1.5, 2));
  snapshot.write(run, {{"steps", 2}});
  EXPECT_EQ(partFiles(dir), std::vector<std::string>{"keyframes.000001.pcd"});
  expectSameMap(loadRunMap(runSnapshotDir(dir)), run);
}

TEST(RunSnapshot, ABadPartListIsAnErrorNamingTheReport) {
  const std::string dir = runDir("bad");
  RunMap run = emptyRun();
  run.map.add(keyframeAt(0, 2));
  RunSnapshot(dir).write(run, {{"steps", 1}});
  const std::string report_path = runSnapshotDir(dir) + "/report.json";
  auto expectError = [&](const nlohmann::json& point_files, const std::string& named) {
    nlohmann::json report = snapshotReport(dir);
    report["run_map"]["point_files"] = point_files;
    std::ofstream(report_path) << report.dump();
    try {
      loadRunMap(runSnapshotDir(dir));
      ADD_FAILURE() << point_files.dump() << " loaded";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
    }
  };
  expectError({{{"file", "../keyframes.pcd"}, {"points", 2}}}, report_path);  // outside the snapshot
  expectError(nlohmann::json::object(), report_path);                          // not a list
  expectError({{{"file", "keyframes.000000.pcd"}, {"points", 3}}}, "keyframes.000000.pcd");  // a count off
  expectError({{{"file", "keyframes.000009.pcd"}, {"points", 2}}}, "keyframes.000009.pcd");  // missing
}
