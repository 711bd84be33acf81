// valerant_export: the map of a finished run directory as files game engines and ROS
// tools load (see map/run_exports.h for the formats and their frames).
//
//   valerant_export --run DIR --out DIR [--formats ply,pcd,bt,grid,obj,glb,walkable,png] [--force]
//   (--help: every flag)
//
// Rebuilds the map from the run's own files (map/run_map.h), writes the formats (all by
// default) and report.json into --out, and prints one JSON summary line. On an engine
// run (report.json names the map, gt_trajectory.txt exists) the report also holds the
// exported walkable area's precision and recall against the reachable floor
// (eval/walkable_truth.h). Never overwrites a file unless --force. The configuration is
// the run's own (its config.yaml): the one that made the map, so no --config or --set.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "command_line.h"
#include "valerant/common/error.h"
#include "valerant/common/joined.h"
#include "valerant/common/output_file.h"
#include "valerant/common/tum_trajectory.h"
#include "valerant/eval/trajectory_metrics.h"
#include "valerant/eval/walkable_truth.h"
#include "valerant/map/run_exports.h"
#include "valerant/map/run_map.h"
#include "valerant/world/quake3/quake3_map.h"
#include "valerant/world/quake3/reachable_floor.h"
#include "valerant/world/quake3/units.h"

using namespace valerant;
namespace fs = std::filesystem;

namespace {

// Walkable precision / recall of `walkable_path` against the engine map the run
// explored, the SLAM map tied to the BSP frame through the ground-truth trajectory.
nlohmann::json walkableGroundTruth(const RunMap& run, const std::string& run_dir, const std::string& walkable_path) {
  const std::string truth_path = (fs::path(run_dir) / "gt_trajectory.txt").string();
  // A run of the learned world from a screenshot has null for both: it explored no level.
  const auto map_field = run.report.find("map"), spawn_field = run.report.find("spawn");
  const bool engine_run = map_field != run.report.end() && map_field->is_string() &&
                          !map_field->get<std::string>().empty() && spawn_field != run.report.end() &&
                          spawn_field->is_number_integer();
  if (!engine_run || !fs::exists(truth_path))
    return {{"available", false}, {"reason", "not an engine run (no map name or gt_trajectory.txt)"}};
  const std::string map_name = map_field->get<std::string>();
  std::vector<Eigen::Isometry3d> truth;
  for (const auto& p : readTumTrajectory(truth_path)) {
    Eigen::Isometry3d pose = p.pose;
    pose.translation() /= quake3::kUnitsPerMetre;
    truth.push_back(pose);
  }
  if (truth.size() != run.trajectory.size())
    throw InputError(truth_path, "holds " + std::to_string(truth.size()) + " poses, trajectory.txt " +
                                     std::to_string(run.trajectory.size()));
  const TrajectoryError ate = trajectoryError(run.trajectory, truth);
  if (!ate.aligned) return {{"available", false}, {"reason", "the trajectory is too short to align"}};

  const auto map = quake3::loadQuake3Map(map_name, run.config.world.patch_level);
  const auto spawns = map->bsp.spawnPoints();
  const int spawn = spawn_field->get<int>();
  if (spawn < 0 || spawn >= static_cast<int>(spawns.size()))
    throw InputError(run_dir + "/report.json", "spawn " + std::to_string(spawn) + " is not a spawn of " + map_name);
  const auto reachable = quake3::floodFillReachableFloor(*map->collision, spawns[spawn].origin);
  const WalkableTruth t = evaluateWalkableTruth(readWalkableJson(walkable_path),
                                                run.floorGrid(run.config.exports.walkable_cell_fraction), run.frame,
                                                ate.alignment, reachable, spawns[spawn].origin);
  return {{"available", true},
          {"walkable_precision", t.precision},
          {"walkable_recall_explored", t.recall_explored},
          {"walkable_recall_all", t.recall_all},
          {"walkable_cells", t.walkable_cells},
          {"walkable_cells_reachable", t.walkable_cells_reachable},
          {"reachable_cells", t.reachable_cells},
          {"reachable_cells_explored", t.reachable_cells_explored},
          {"reachable_cells_explored_walkable", t.reachable_cells_explored_walkable},
          {"reachable_cell_m", reachable.cell_size / quake3::kUnitsPerMetre},
          {"truth_metres_per_unit", ate.alignment.scale},
          {"ate_rmse_m", ate.ate_rmse}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Rebuilds the map of a finished run from its own files and exports it as files game engines and "
      "ROS tools load.",
      "valerant_export"};
  tools::useToolConventions(app);
  std::string run_dir, out, formats_text = joined(exportFormats(), ",");
  tools::addPath(app, "--run", run_dir, "finished run folder (valerant_explore, the explorer node)", "DIR")
      ->required();
  tools::addPath(app, "--out", out, "export folder", "DIR")->required();
  app.add_option("--formats", formats_text, "formats, comma-separated")->type_name("LIST")->capture_default_str();
  const CLI::Option* force = app.add_flag("--force", "overwrite files the export folder holds");
  return tools::runTool(app, argc, argv, [&] {
    const std::vector<std::string> formats = tools::checkFlagValues([&] { return parseFormats(formats_text); });
    const bool overwrite = force->count() > 0;
    if (fs::exists(out) && fs::exists(run_dir) && fs::equivalent(out, run_dir))
      throw tools::UsageError("--out " + out, "is the run directory; its files are the export's input");

    const RunMap run = loadRunMap(run_dir);
    fs::create_directories(out);
    const std::string report_path = (fs::path(out) / "report.json").string();
    requireWritable(report_path, overwrite);
    nlohmann::json report = exportRunMap(run, formats, out, overwrite);
    report["tool"] = "valerant_export";
    report["run"] = run_dir;
    report["formats"] = formats;
    if (std::count(formats.begin(), formats.end(), "walkable"))
      report["ground_truth"] = walkableGroundTruth(run, run_dir, (fs::path(out) / "walkable.json").string());
    report["files"].push_back("report.json");
    writeFileAtomically(report_path, report.dump(2) + '\n');
    std::cout << report.dump() << std::endl;
    return 0;
  });
}
