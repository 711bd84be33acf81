#include "valerant/map/run_map.h"

#define PCL_NO_PRECOMPILE
#include <pcl/common/io.h>
#include <pcl/console/print.h>
#include <pcl/conversions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <fcntl.h>
#include <stdio.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "valerant/common/error.h"
#include "valerant/common/output_file.h"
#include "valerant/common/tum_trajectory.h"

namespace valerant {
namespace {

struct KeyframePoint {
  PCL_ADD_POINT4D;
  PCL_ADD_RGB;
  float confidence;
  float h;
  std::uint32_t keyframe;
  PCL_MAKE_ALIGNED_OPERATOR_NEW
};

}  // namespace
}  // namespace valerant

POINT_CLOUD_REGISTER_POINT_STRUCT(valerant::KeyframePoint,
                                  (float, x, x)(float, y, y)(float, z, z)(float, rgb, rgb)(float, confidence,
                                                                                           confidence)(
                                      float, h, h)(std::uint32_t, keyframe, keyframe))

namespace valerant {
namespace {

namespace fs = std::filesystem;

const char* const kKeyframePoints = "keyframes.pcd";
const char* const kKeyframePoses = "keyframes.txt";
const char* const kTrajectory = "trajectory.txt";
const char* const kConfig = "config.yaml";
const char* const kReport = "report.json";
const char* const kSnapshot = "snapshot";

std::string inside(const std::string& dir, const char* name) { return (fs::path(dir) / name).string(); }

void requireFile(const std::string& path) {
  if (!fs::is_regular_file(path)) throw InputError(path, "missing (not a finished valerant_explore run?)");
}

nlohmann::json readJson(const std::string& path) {
  requireFile(path);
  std::ifstream in(path);
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, "truncated or invalid JSON (" + std::string(e.what()) + ")");
  }
}

size_t count(const nlohmann::json& run_map, const char* key, const std::string& source) {
  if (!run_map.contains(key) || !run_map[key].is_number_unsigned())
    throw InputError(source, std::string("run_map: missing count '") + key + "'");
  return run_map[key].get<size_t>();
}

void requireCount(const std::string& path, size_t found, size_t expected, const char* what) {
  if (found != expected) {
    std::ostringstream s;
    s << "holds " << found << " " << what << ", report.json says " << expected << " (truncated?)";
    throw InputError(path, s.str());
  }
}

std::vector<Eigen::Isometry3d> readPoses(const std::string& path) {
  requireFile(path);
  std::vector<Eigen::Isometry3d> poses;
  for (const auto& p : readTumTrajectory(path)) poses.push_back(p.pose);
  return poses;
}

pcl::PointCloud<KeyframePoint> readKeyframePoints(const std::string& path) {
  requireFile(path);
  pcl::PCLPointCloud2 blob;
  // PCL reports its own parse errors on the console; ours names the file in one line.
  const auto verbosity = pcl::console::getVerbosityLevel();
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  const int status = pcl::io::loadPCDFile(path, blob);
  pcl::console::setVerbosityLevel(verbosity);
  if (status != 0) throw InputError(path, "PCL cannot read it (truncated or not a PCD file)");
  for (const char* name : {"x", "y", "z", "rgb", "confidence", "h", "keyframe"})
    if (pcl::getFieldIndex(blob, name) < 0) throw InputError(path, std::string("has no field '") + name + "'");
  pcl::PointCloud<KeyframePoint> cloud;
  pcl::fromPCLPointCloud2(blob, cloud);
  return cloud;
}

}  // namespace

CoverageGrid RunMap::grid() const {
  return CoverageGrid(config.policy, frame.anchorFloor(), frame.forward,
                      config.world.d_fwd_units / config.world.eye_height_units);
}

FloorGrid RunMap::floorGrid(double cell_fraction) const {
  const CoverageGrid anchor_grid = grid();
  return map.floorGrid(anchor_grid, cell_fraction * anchor_grid.cellSize());
}

nlohmann::json saveRunMap(const std::string& dir, const RunMap& run, bool overwrite) {
  const std::string points_path = inside(dir, kKeyframePoints), poses_path = inside(dir, kKeyframePoses);
  for (const auto& path : {points_path, poses_path}) requireWritable(path, overwrite);
  const std::string config_copy = inside(dir, kConfig);
  if (!fs::is_regular_file(config_copy))
    throw InputError(config_copy, "missing: copy the run's configuration first (saveRunConfig)");

  pcl::PointCloud<KeyframePoint> cloud;
  std::vector<StampedPose> poses;
  const auto& keyframes = run.map.keyframes();
  for (size_t k = 0; k < keyframes.size(); ++k) {
    poses.push_back({static_cast<double>(k), keyframes[k]->camera_to_map});
    for (const auto& p : keyframes[k]->points) {
      KeyframePoint q;
      q.x = p.position.x(), q.y = p.position.y(), q.z = p.position.z();
      q.r = p.rgb[0], q.g = p.rgb[1], q.b = p.rgb[2], q.a = 255;
      q.confidence = p.confidence;
      q.h = p.h;
      q.keyframe = static_cast<std::uint32_t>(k);
      cloud.push_back(q);
    }
  }
  // PCL refuses to write a cloud without points; an empty map still gets a valid file.
  if (cloud.empty()) {
    writeFileAtomically(points_path,
                        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
                        "FIELDS x y z rgb confidence h keyframe\nSIZE 4 4 4 4 4 4 4\nTYPE F F F F F F U\n"
                        "COUNT 1 1 1 1 1 1 1\nWIDTH 0\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 0\nDATA ascii\n");
  } else {
    writeThroughTemporary(points_path, "PCL's PCD writer", [&](const std::string& temporary) {
      return pcl::io::savePCDFileBinaryCompressed(temporary, cloud) == 0;
    });
  }
  writeTumTrajectory(poses_path, poses);
  return {{"frame", toJson(run.frame)},
          {"config_bytes", fs::file_size(config_copy)},
          {"keyframes", keyframes.size()},
          {"points", cloud.size()},
          {"trajectory_poses", run.trajectory.size()}};
}

void saveRunConfig(const std::string& dir, const ConfigDocument& config, bool overwrite) {
  const std::string copy = inside(dir, kConfig);
  requireWritable(copy, overwrite);
  writeFileAtomically(copy, config.yaml());
}

std::string runSnapshotDir(const std::string& dir) { return inside(dir, kSnapshot); }

void saveRunSnapshot(const std::string& dir, const RunMap& run, nlohmann::json report) {
  const std::string config_path = inside(dir, kConfig);
  requireFile(config_path);
  const std::string building = inside(dir, ".snapshot.partial");
  fs::remove_all(building);  // a build a killed process left behind
  fs::create_directories(building);
  try {
    std::ifstream in(config_path, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    if (!in && !in.eof()) throw InputError(config_path, "cannot read");
    writeFileAtomically(inside(building, kConfig), bytes.str());
    report["run_map"] = saveRunMap(building, run, false);
    std::vector<StampedPose> trajectory;
    for (size_t i = 0; i < run.trajectory.size(); ++i) trajectory.push_back({double(i), run.trajectory[i]});
    writeTumTrajectory(inside(building, kTrajectory), trajectory);
    report["snapshot"] = true;
    writeFileAtomically(inside(building, kReport), report.dump(2) + '\n');
  } catch (...) {
    std::error_code ignored;  // the failure itself is what the caller hears about
    fs::remove_all(building, ignored);
    throw;
  }
  const std::string snapshot = runSnapshotDir(dir);
  // Swap the new snapshot in: one rename, whether or not an old one is there.
  if (fs::exists(snapshot)) {
    if (::renameat2(AT_FDCWD, building.c_str(), AT_FDCWD, snapshot.c_str(), RENAME_EXCHANGE) != 0)
      throw InputError(snapshot, std::string("cannot swap in the new snapshot: ") + std::strerror(errno));
    fs::remove_all(building);  // now the old snapshot
  } else if (::rename(building.c_str(), snapshot.c_str()) != 0) {
    throw InputError(snapshot, std::string("cannot move the snapshot into place: ") + std::strerror(errno));
  }
}

RunMap loadRunMap(const std::string& dir) {
  if (!fs::is_directory(dir)) throw InputError(dir, "no such run directory");
  const std::string report_path = inside(dir, kReport);
  if (!fs::exists(report_path) && fs::is_regular_file(inside(runSnapshotDir(dir), kReport)))
    throw InputError(report_path, "missing: the run did not finish; the map of its committed steps is in " +
                                      runSnapshotDir(dir) + " (a run directory of its own)");
  nlohmann::json report = readJson(report_path);
  if (!report.is_object() || !report.contains("run_map") || !report["run_map"].is_object())
    throw InputError(report_path, "has no run_map (made before runs kept their map; rerun the episode)");
  const nlohmann::json& run_map = report["run_map"];
  const MapFrame frame = mapFrameFromJson(run_map.value("frame", nlohmann::json()), report_path);

  const std::string config_path = inside(dir, kConfig);
  requireFile(config_path);
  requireCount(config_path, fs::file_size(config_path), count(run_map, "config_bytes", report_path), "bytes");
  const Config config = loadConfig(config_path);

  const std::string poses_path = inside(dir, kKeyframePoses);
  const auto keyframe_poses = readPoses(poses_path);
  requireCount(poses_path, keyframe_poses.size(), count(run_map, "keyframes", report_path), "keyframe poses");

  const std::string points_path = inside(dir, kKeyframePoints);
  const auto cloud = readKeyframePoints(points_path);
  requireCount(points_path, cloud.size(), count(run_map, "points", report_path), "points");
  std::vector<std::shared_ptr<FusedKeyframe>> keyframes;
  for (const auto& pose : keyframe_poses) {
    keyframes.push_back(std::make_shared<FusedKeyframe>());
    keyframes.back()->id = newKeyframeId();
    keyframes.back()->camera_to_map = pose;
  }
  for (const auto& q : cloud) {
    if (q.keyframe >= keyframes.size())
      throw InputError(points_path, "a point names keyframe " + std::to_string(q.keyframe) + ", beyond " +
                                        poses_path);
    keyframes[q.keyframe]->points.push_back({q.getVector3fMap(), {q.r, q.g, q.b}, q.confidence, q.h});
  }

  const std::string trajectory_path = inside(dir, kTrajectory);
  auto trajectory = readPoses(trajectory_path);
  requireCount(trajectory_path, trajectory.size(), count(run_map, "trajectory_poses", report_path), "poses");

  RunMap run{config, MapFusion(config.map, config.collision), frame, std::move(trajectory), std::move(report)};
  for (auto& kf : keyframes) run.map.add(std::move(kf));
  return run;
}

}  // namespace valerant
