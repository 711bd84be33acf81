#pragma once
// A run's map with everything its exports need, and how it is kept in a run directory
// so that valerant_export rebuilds it without the episode:
//   keyframes.pcd   every fused point (binary compressed PCD): x y z rgb confidence,
//                   h (floor-normalised height) and keyframe (index of its keyframe)
//   keyframes.txt   keyframe camera poses, map frame (TUM; stamp = keyframe index)
//   trajectory.txt  committed camera poses, map frame (TUM; written by valerant_explore)
//   config.yaml     the run's whole configuration (base files merged, the tool's flags
//                   and --set overrides applied: config.h ConfigDocument::yaml)
//   report.json     "run_map": the map frame (map_frame.h) and the number of keyframes,
//                   points, trajectory poses and config bytes, so a truncated file is caught
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

// Writes keyframes.pcd and keyframes.txt into `dir` (which must hold config.yaml
// already: saveRunConfig); returns the "run_map" object for report.json. Never
// overwrites unless asked.
nlohmann::json saveRunMap(const std::string& dir, const RunMap& run, bool overwrite);
// Writes the run's configuration to `dir`/config.yaml.
void saveRunConfig(const std::string& dir, const ConfigDocument& config, bool overwrite);

// The map of the steps committed so far, kept in `dir`/snapshot as a small run
// directory of its own (config.yaml, keyframes.pcd, keyframes.txt, trajectory.txt and a
// report.json holding `report` with its run_map) that loadRunMap and valerant_export
// read. The new snapshot is built beside the old one and swapped in with one atomic
// rename, so a process killed at any moment leaves a whole snapshot. `dir` must hold
// config.yaml.
void saveRunSnapshot(const std::string& dir, const RunMap& run, nlohmann::json report);
// The folder saveRunSnapshot keeps: `dir`/snapshot.
std::string runSnapshotDir(const std::string& dir);

// Reads a finished run directory. A missing, truncated or inconsistent file throws
// InputError naming that file.
RunMap loadRunMap(const std::string& dir);

}  // namespace valerant
