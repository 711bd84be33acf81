#pragma once
// A run's map with everything its exports need, and how it is kept in a run directory
// so that valerant_export rebuilds it without the episode:
//   keyframes.pcd   every fused point (keyframe_points_file.h)
//   keyframes.txt   keyframe camera poses, map frame (TUM; stamp = keyframe index)
//   trajectory.txt  committed camera poses, map frame (TUM; written by valerant_explore)
//   config.yaml     the run's whole configuration (base files merged, the tool's flags
//                   and --set overrides applied: config.h ConfigDocument::yaml)
//   report.json     "run_map": the map frame (map_frame.h) and the number of keyframes,
//                   points, trajectory poses and config bytes, so a truncated file is caught;
//                   a snapshot (run_snapshot.h) lists its point files in "point_files"
//                   ({"file", "points"} each, in keyframe order) instead of keyframes.pcd
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/geometry/coverage_grid.h"
#include "valerant/map/map_frame.h"
#include "valerant/map/map_fusion.h"

namespace valerant {

struct RunMap {
  Config config;
  MapFusion map;
  MapFrame frame;
  std::vector<Eigen::Isometry3d> trajectory;  // committed camera poses, map frame
  nlohmann::json report;                      // the run's report.json (loaded runs only)

  // The exploration grid of the run, rebuilt from its anchor.
  CoverageGrid grid() const;
  // The 2D floor grid of the map over that grid, cells `cell_fraction` of its cell.
  FloorGrid floorGrid(double cell_fraction) const;
};

// The names of a run directory's files (above).
namespace run_files {
inline constexpr char kKeyframePoints[] = "keyframes.pcd";
inline constexpr char kKeyframePoses[] = "keyframes.txt";
inline constexpr char kTrajectory[] = "trajectory.txt";
inline constexpr char kConfig[] = "config.yaml";
inline constexpr char kReport[] = "report.json";
}  // namespace run_files

// Writes the camera poses of `map`'s keyframes to `path` (keyframes.txt).
void writeKeyframePoses(const std::string& path, const MapFusion& map);
// report.json's "run_map" object for `run`, whose config.yaml holds `config_bytes` and
// whose point files hold `points`.
nlohmann::json runMapReport(const RunMap& run, size_t config_bytes, size_t points);

// Writes keyframes.pcd and keyframes.txt into `dir` (which must hold config.yaml
// already: saveRunConfig); returns the "run_map" object for report.json. Never
// overwrites unless asked.
nlohmann::json saveRunMap(const std::string& dir, const RunMap& run, bool overwrite);
// Writes the run's configuration to `dir`/config.yaml.
void saveRunConfig(const std::string& dir, const ConfigDocument& config, bool overwrite);

// The folder where a run keeps the map of its committed steps until it ends: `dir`/snapshot
// (run_snapshot.h).
std::string runSnapshotDir(const std::string& dir);

// Reads a finished run directory. A missing, truncated or inconsistent file throws
// InputError naming that file.
RunMap loadRunMap(const std::string& dir);

}  // namespace valerant
