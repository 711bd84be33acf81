// A run directory as valerant_export sees it: the map kept by the run reads back
// (keyframes.pcd with PCL, keyframes.txt / trajectory.txt as TUM, report.json), every
// export format comes out of one code path identically from the episode's map and from
// the files, nothing is overwritten without --force, and a missing or truncated file is
// named in the error.
#include <gtest/gtest.h>
#include <pcl/io/pcd_io.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "valerant/common/error.h"
#include "valerant/common/tum_trajectory.h"
#include "valerant/map/run_exports.h"
#include "valerant/map/run_map.h"

using namespace valerant;
namespace fs = std::filesystem;

namespace {

constexpr double kEye = 0.5;  // camera height over the floor, map units (a scaled SLAM map)

Eigen::Isometry3d cameraAt(double x, double y) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  // Optical axis along +x, image y down (-z): the camera looks along the corridor.
  pose.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  pose.translation() = Eigen::Vector3d(x, y, kEye);
  return pose;
}

// What a camera at (x, 0) sees of a corridor 2 wide and 6 long along x: floor z = 0
// and walls y = +-1 up to 1.5, points every 0.05 within 2 units ahead.
KeyframeCloud corridorView(double x0) {
  KeyframeCloud kf;
  kf.camera_to_map = cameraAt(x0, 0);
  auto add = [&](double x, double y, double z) {
    CloudPoint p;
    p.position = Eigen::Vector3d(x, y, z).cast<float>();
    p.rgb = {static_cast<uint8_t>(100 + 50 * z), 120, 80};
    p.confidence = 10;
    kf.points.push_back(p);
  };
  for (int i = 0; i <= 40; ++i) {
    const double x = x0 + 0.05 * i;
    for (int j = 0; j <= 40; ++j) add(x, -1 + 0.05 * j, 0);
    for (int k = 1; k <= 30; ++k) {
      add(x, -1, 0.05 * k);
      add(x, 1, 0.05 * k);
    }
  }
  return kf;
}

FloorPlane floorUnder(const Eigen::Isometry3d& camera) {
  FloorPlane f;
  f.n = Eigen::Vector3d::UnitZ();
  f.c = camera.translation();
  f.reliable = true;
  return f;
}

RunMap corridorRun() {
  const Config config = loadConfig(defaultConfigPath());
  RunMap run{config, MapFusion(config.map, config.collision),
             mapFrameOf(floorUnder(cameraAt(0, 0)), Eigen::Vector3d::UnitX(), false, config), {},
             nlohmann::json::object()};
  for (double x : {0.0, 2.0, 4.0}) run.map.fuse(corridorView(x), floorUnder(cameraAt(x, 0)));
  // Steps of 1/8: exact in the 9 digits of a TUM file, so files rebuild bit for bit.
  for (int i = 0; i <= 40; ++i) run.trajectory.push_back(cameraAt(0.125 * i, 0));
  return run;
}

std::string freshDir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/valerant_export_run_" + name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// The files valerant_explore leaves for the export.
void saveRun(const RunMap& run, const std::string& dir) {
  saveRunConfig(dir, ConfigDocument::load(defaultConfigPath()), false);
  nlohmann::json report = {{"tool", "valerant_explore"}, {"run_map", saveRunMap(dir, run, false)}};
  writeTumTrajectory(dir + "/trajectory.txt", run.trajectory);
  std::ofstream(dir + "/report.json") << report.dump(2);
}

std::string contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The InputError loadRunMap throws for `dir`, or a failure.
std::string loadError(const std::string& dir) {
  try {
    loadRunMap(dir);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << dir << " loaded";
  return "";
}

}  // namespace

TEST(ExportRun, KeyframesPcdReadsBackWithPclAndRebuildsTheMap) {
  const RunMap run = corridorRun();
  const std::string dir = freshDir("rebuild");
  saveRun(run, dir);

  pcl::PCLPointCloud2 pcd;
  ASSERT_EQ(pcl::io::loadPCDFile(dir + "/keyframes.pcd", pcd), 0);
  EXPECT_EQ(pcd.width * pcd.height, run.map.pointCount());
  for (const char* field : {"h", "keyframe", "confidence", "rgb"}) EXPECT_GE(pcl::getFieldIndex(pcd, field), 0);

  const RunMap back = loadRunMap(dir);
  ASSERT_EQ(back.map.keyframes().size(), 3u);
  EXPECT_EQ(back.map.pointCount(), run.map.pointCount());
  EXPECT_EQ(back.trajectory.size(), run.trajectory.size());
  const FusedPoint& a = run.map.keyframes()[1]->points[77];
  const FusedPoint& b = back.map.keyframes()[1]->points[77];
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.h, b.h);
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_TRUE(back.map.keyframes()[2]->camera_to_map.isApprox(run.map.keyframes()[2]->camera_to_map, 1e-8));
  EXPECT_TRUE(back.frame.mapToAsset().isApprox(run.frame.mapToAsset()));
  EXPECT_DOUBLE_EQ(back.frame.metres_per_unit, 50.0 / 32.0 / kEye);  // eye height scale
}

TEST(ExportRun, OneCodePathFromTheEpisodeAndFromTheFiles) {
  const RunMap run = corridorRun();
  const std::string dir = freshDir("one_path"), from_memory = freshDir("from_memory"), from_files = freshDir("from_files");
  saveRun(run, dir);
  const nlohmann::json a = exportRunMap(run, exportFormats(), from_memory, false);
  const nlohmann::json b = exportRunMap(loadRunMap(dir), exportFormats(), from_files, false);
  EXPECT_TRUE(a["skipped"].empty()) << a["skipped"].dump();
  EXPECT_GT(a["mesh"]["triangles"].get<int>(), 1000);
  EXPECT_GT(a["walkable"]["area_m2"].get<double>(), 1.0);
  ASSERT_EQ(a["files"], b["files"]);
  ASSERT_EQ(a["files"].size(), exportFiles(exportFormats()).size());
  for (const auto& name : exportFiles(exportFormats()))
    EXPECT_EQ(contents(from_memory + "/" + name), contents(from_files + "/" + name)) << name;
  // The pictures are the map, not an empty background.
  for (const char* png : {"overview.png", "orbit.png"}) {
    const cv::Mat image = cv::imread(from_files + "/" + png);
    ASSERT_FALSE(image.empty()) << png;
    cv::Scalar mean, spread;
    cv::meanStdDev(image, mean, spread);
    EXPECT_GT(spread[0] + spread[1] + spread[2], 10.0) << png;
  }
}

TEST(ExportRun, NeverOverwritesWithoutForce) {
  const RunMap run = corridorRun();
  const std::string out = freshDir("overwrite");
  exportRunMap(run, parseFormats("grid,walkable"), out, false);
  const auto before = fs::last_write_time(out + "/walkable.json");
  // ply is new but walkable.json exists: nothing at all is written.
  try {
    exportRunMap(run, parseFormats("ply,walkable"), out, false);
    FAIL() << "overwrote walkable.json";
  } catch (const InputError& e) {
    EXPECT_EQ(e.input(), out + "/walkable.json");
  }
  EXPECT_FALSE(fs::exists(out + "/map.ply"));
  EXPECT_EQ(fs::last_write_time(out + "/walkable.json"), before);
  EXPECT_NO_THROW(exportRunMap(run, parseFormats("ply,walkable"), out, true));
  EXPECT_TRUE(fs::exists(out + "/map.ply"));
}

TEST(ExportRun, MissingOrTruncatedFilesAreNamed) {
  const std::string good = freshDir("good");
  saveRun(corridorRun(), good);
  EXPECT_NE(loadError(good + "/nowhere").find("no such run directory"), std::string::npos);
  for (const char* name : {"report.json", "config.yaml", "keyframes.pcd", "keyframes.txt", "trajectory.txt"}) {
    const std::string dir = freshDir("broken");
    fs::copy(good, dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
    fs::remove(dir + "/" + name);
    const std::string missing = loadError(dir);
    EXPECT_NE(missing.find(dir + "/" + name), std::string::npos) << missing;
    EXPECT_NE(missing.find("missing"), std::string::npos) << missing;

    fs::copy_file(good + "/" + name, dir + "/" + name);
    fs::resize_file(dir + "/" + name, fs::file_size(dir + "/" + name) * 2 / 3);
    const std::string truncated = loadError(dir);
    EXPECT_NE(truncated.find(dir + "/" + name), std::string::npos) << truncated;
    EXPECT_EQ(truncated.find('\n'), std::string::npos) << truncated;  // one line
  }
}

TEST(ExportRun, EmptyMapSkipsWhatNeedsPoints) {
  RunMap run = corridorRun();
  run.map.truncate(0);
  const std::string dir = freshDir("empty"), out = freshDir("empty_out");
  saveRun(run, dir);
  const RunMap back = loadRunMap(dir);
  EXPECT_EQ(back.map.pointCount(), 0u);
  const nlohmann::json result = exportRunMap(back, exportFormats(), out, false);
  for (const char* format : {"ply", "pcd", "bt", "obj", "glb", "png"}) EXPECT_TRUE(result["skipped"].contains(format));
  EXPECT_TRUE(fs::exists(out + "/grid.pgm"));
  EXPECT_TRUE(fs::exists(out + "/walkable.json"));
}

TEST(ExportRun, FormatListsAreChecked) {
  EXPECT_EQ(parseFormats("glb,ply"), (std::vector<std::string>{"glb", "ply"}));
  EXPECT_EQ(exportFiles(parseFormats("grid,png")),
            (std::vector<std::string>{"grid.pgm", "grid.yaml", "overview.png", "orbit.png"}));
  EXPECT_THROW(parseFormats("ply,fbx"), InputError);
  EXPECT_THROW(parseFormats("ply,ply"), InputError);
  EXPECT_THROW(parseFormats(""), InputError);
}
