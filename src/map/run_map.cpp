#include "valerant/map/run_map.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "valerant/common/error.h"
#include "valerant/common/output_file.h"
#include "valerant/common/tum_trajectory.h"
#include "valerant/map/keyframe_points_file.h"

namespace valerant {

using namespace run_files;

namespace {

namespace fs = std::filesystem;

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

}  // namespace

CoverageGrid RunMap::grid() const {
  return CoverageGrid(config.policy, frame.anchorFloor(), frame.forward,
                      config.world.d_fwd_units / config.world.eye_height_units);
}

FloorGrid RunMap::floorGrid(double cell_fraction) const {
  const CoverageGrid anchor_grid = grid();
  return map.floorGrid(anchor_grid, cell_fraction * anchor_grid.cellSize());
}

void writeKeyframePoses(const std::string& path, const MapFusion& map) {
  std::vector<Eigen::Isometry3d> poses;
  for (const auto& keyframe : map.keyframes()) poses.push_back(keyframe->camera_to_map);
  writeTumTrajectory(path, poses);
}

nlohmann::json runMapReport(const RunMap& run, size_t config_bytes, size_t points) {
  return {{"frame", toJson(run.frame)},
          {"config_bytes", config_bytes},
          {"keyframes", run.map.keyframes().size()},
          {"points", points},
          {"trajectory_poses", run.trajectory.size()}};
}

nlohmann::json saveRunMap(const std::string& dir, const RunMap& run, bool overwrite) {
  const std::string points_path = inside(dir, kKeyframePoints), poses_path = inside(dir, kKeyframePoses);
  for (const auto& path : {points_path, poses_path}) requireWritable(path, overwrite);
  const std::string config_copy = inside(dir, kConfig);
  if (!fs::is_regular_file(config_copy))
    throw InputError(config_copy, "missing: copy the run's configuration first (saveRunConfig)");

  const auto& keyframes = run.map.keyframes();
  const size_t points = writeKeyframePoints(points_path, keyframes, 0, keyframes.size());
  writeKeyframePoses(poses_path, run.map);
  return runMapReport(run, fs::file_size(config_copy), points);
}

void saveRunConfig(const std::string& dir, const ConfigDocument& config, bool overwrite) {
  const std::string copy = inside(dir, kConfig);
  requireWritable(copy, overwrite);
  writeFileAtomically(copy, config.yaml());
}

std::string runSnapshotDir(const std::string& dir) { return inside(dir, kSnapshot); }

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

  std::vector<std::shared_ptr<FusedKeyframe>> keyframes;
  for (const auto& pose : keyframe_poses) {
    keyframes.push_back(std::make_shared<FusedKeyframe>());
    keyframes.back()->id = newKeyframeId();
    keyframes.back()->camera_to_map = pose;
  }
  // One file, or a snapshot's parts (run_snapshot.h).
  std::vector<std::pair<std::string, size_t>> point_files;  // name, points
  if (run_map.contains("point_files")) {
    if (!run_map["point_files"].is_array()) throw InputError(report_path, "run_map: point_files is not a list");
    for (const auto& part : run_map["point_files"]) {
      const std::string name =
          part.is_object() && part.contains("file") && part["file"].is_string() ? part["file"].get<std::string>() : "";
      if (name.empty() || name.find('/') != std::string::npos || name[0] == '.')
        throw InputError(report_path, "run_map: point_files holds an entry that is no file name in the run directory");
      point_files.emplace_back(name, count(part, "points", report_path));
    }
  } else {
    point_files.emplace_back(kKeyframePoints, count(run_map, "points", report_path));
  }
  for (const auto& [name, points] : point_files) {
    const std::string points_path = inside(dir, name.c_str());
    requireCount(points_path, readKeyframePoints(points_path, keyframes), points, "points");
  }

  const std::string trajectory_path = inside(dir, kTrajectory);
  auto trajectory = readPoses(trajectory_path);
  requireCount(trajectory_path, trajectory.size(), count(run_map, "trajectory_poses", report_path), "poses");

  RunMap run{config, MapFusion(config.map, config.collision), frame, std::move(trajectory), std::move(report)};
  for (auto& kf : keyframes) run.map.add(std::move(kf));
  return run;
}

}  // namespace valerant
