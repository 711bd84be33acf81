// valerant_explore: one exploration episode on the engine world, without ROS.
//
//   valerant_explore --map NAME [--spawn I] [--slam visual|oracle] [--budget N]
//                    [--no-rf] [--no-col-pc] [--no-col-depth] [--no-dp] [--seed S]
//                    [--policy valerant|random|forward|frontier]
//                    [--config FILE] [--force] --out DIR
//
// Writes map.ply, map.pcd, map.bt, grid.pgm + grid.yaml, trajectory.txt (TUM, SLAM
// frame), gt_trajectory.txt (TUM, BSP frame, game units), decisions.jsonl, topdown.png
// and report.json into DIR; prints one JSON summary line. Ctrl-C stops after the
// current step and still writes everything.
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <octomap/ColorOcTree.h>

#include "cli_args.h"
#include "valerant/common/tum_trajectory.h"
#include "valerant/eval/episode_truth.h"
#include "valerant/eval/map_accuracy.h"
#include "valerant/explore/episode.h"
#include "valerant/explore/episode_json.h"
#include "valerant/explore/topdown_image.h"
#include "valerant/map/map_exports.h"
#include "valerant/slam/slam_factory.h"
#include "valerant/world/quake3/quake3_world.h"

using namespace valerant;
namespace fs = std::filesystem;

namespace {

std::atomic<bool> g_stop{false};
void onSignal(int) { g_stop = true; }

constexpr float kSurfaceSamplesPerSquareMetre = 50;  // 14 cm spacing: accuracy to ~7 cm
constexpr int kTopdownPixelsPerCell = 16;  // 16 px per metre-sized cell: a 40 m map is ~700 px

void writeOutputs(const Episode& episode, const quake3::Quake3World& world, const std::string& out, bool overwrite,
                  nlohmann::json& report) {
  const Config& config = episode.config();
  const double kappa = episode.anchorEyeHeight();
  const std::vector<FusedPoint> cloud = episode.map().voxelCloud(config.map.voxel_eye_heights * kappa);
  nlohmann::json files = nlohmann::json::array();
  if (!cloud.empty()) {
    writeCloudPly(out + "/map.ply", cloud, overwrite);
    writeCloudPcd(out + "/map.pcd", cloud, overwrite);
    auto tree = episode.map().octree(config.map.octree_eye_heights * kappa);
    writeOctreeBt(out + "/map.bt", *tree, overwrite);
    files.insert(files.end(), {"map.ply", "map.pcd", "map.bt"});
  }
  writeFloorGrid(out + "/grid", episode.map().floorGrid(episode.grid(), config.map.grid_cell_fraction * episode.grid().cellSize()),
                 overwrite);
  std::vector<StampedPose> slam_poses, truth_poses;
  for (size_t i = 0; i < episode.trajectory().size(); ++i) slam_poses.push_back({double(i), episode.trajectory()[i]});
  for (size_t i = 0; i < episode.truth().size(); ++i) truth_poses.push_back({double(i), episode.truth()[i].camera_to_world});
  writeTumTrajectory(out + "/trajectory.txt", slam_poses);
  writeTumTrajectory(out + "/gt_trajectory.txt", truth_poses);
  cv::Mat topdown = drawTopdown(cloud, episode.grid(), episode.trajectory(), episode.history(), episode.failed(),
                                config.collision, kTopdownPixelsPerCell);
  cv::cvtColor(topdown, topdown, cv::COLOR_RGB2BGR);
  if (!cv::imwrite(out + "/topdown.png", topdown)) throw InputError(out + "/topdown.png", "cannot write image");
  files.insert(files.end(), {"grid.pgm", "grid.yaml", "trajectory.txt", "gt_trajectory.txt", "topdown.png",
                             "decisions.jsonl", "report.json"});

  const auto spawn = world.spawnPoints()[config.world.spawn];
  const auto reachable = quake3::floodFillReachableFloor(*world.map().collision, spawn.origin);
  const EpisodeTruth truth = evaluateEpisodeTruth(episode, reachable);
  std::vector<Eigen::Vector3d> map_metres;
  if (truth.aligned)
    for (const auto& p : cloud) map_metres.push_back(truth.map_to_world_metres.apply(p.position.cast<double>()));
  const MapAccuracy accuracy =
      mapAccuracy(map_metres, quake3::sampleSurfaces(world.map().geometry, kSurfaceSamplesPerSquareMetre, config.world.seed),
                  episode.truth(), world.intrinsics());
  int penetration_free_steps = 0;  // committed steps none of whose frames entered solid
  for (const auto& s : episode.history()) {
    if (s.chosen < 0) continue;
    bool clean = true;
    for (const auto& f : s.candidates[s.chosen].truth) clean &= !f.in_solid;
    penetration_free_steps += clean;
  }
  StageSeconds total;
  double wall = 0;
  for (const auto& s : episode.history()) {
    total += s.seconds;
    wall += s.wall_seconds;
  }
  report["files"] = files;
  report["committed_steps"] = episode.committedSteps();
  report["steps"] = episode.history().size();
  report["rewinds"] = episode.rewinds();
  report["failed_cells"] = episode.failed().cells().size();
  report["map_points"] = cloud.size();
  report["stage_seconds"] = toJson(total);
  report["wall_seconds"] = wall;
  report["frames_rendered"] = [&] {
    size_t n = 0;
    for (const auto& s : episode.history())
      for (const auto& c : s.candidates) n += c.truth.size();
    return n;
  }();
  report["ground_truth"] = {{"committed_frames", truth.committed_frames},
                            {"penetrations", truth.penetrating_frames},
                            {"penetration_free_steps", penetration_free_steps},
                            {"reachable_m2", truth.reachable_m2},
                            {"observed_reachable_m2", truth.observed_reachable_m2},
                            {"observed_reachable_percent", truth.observed_reachable_percent},
                            {"aligned", truth.aligned},
                            {"ate_rmse_m", truth.alignment_rmse_m},
                            {"ate_percent", truth.ate_percent},
                            {"observed_percent_by_step", truth.observed_percent_by_step},
                            {"accuracy_median_m", accuracy.median_m},
                            {"accuracy_p90_m", accuracy.p90_m},
                            {"completeness_percent", accuracy.completeness_percent},
                            {"verdicts", truth.verdicts},
                            {"truly_colliding", truth.truly_colliding},
                            {"predicted_colliding", truth.predicted_colliding},
                            {"false_rejections", truth.false_rejections},
                            {"missed_collisions", truth.missed_collisions}};
  std::ofstream(out + "/report.json") << report.dump(2) << '\n';
}

}  // namespace

int main(int argc, char** argv) {
  try {
    tools::CliArgs args(argc, argv, {"--map", "--spawn", "--slam", "--budget", "--seed", "--config", "--out", "--policy"},
                        {"--no-rf", "--no-col-pc", "--no-col-depth", "--no-dp", "--force"});
    Config config = loadConfig(args.get("--config", defaultConfigPath()));
    config.world.map = args.get("--map", config.world.map);
    config.world.spawn = static_cast<int>(args.integer("--spawn", config.world.spawn));
    config.world.seed = static_cast<uint32_t>(args.integer("--seed", config.world.seed));
    config.slam.backend = args.get("--slam", config.slam.backend);
    config.policy.kind = args.get("--policy", config.policy.kind);
    if (config.policy.kind != "valerant" && config.policy.kind != "random" && config.policy.kind != "forward" &&
        config.policy.kind != "frontier")
      throw InputError("--policy " + config.policy.kind, "unknown (known: valerant, random, forward, frontier)");
    config.policy.budget_steps = static_cast<int>(args.integer("--budget", config.policy.budget_steps));
    if (config.policy.budget_steps < 1) throw InputError("--budget", "must be >= 1");
    if (args.has("--no-rf")) config.floor.enabled = false;
    if (args.has("--no-col-pc")) config.collision.pointcloud_enabled = false;
    if (args.has("--no-col-depth")) config.collision.depth_enabled = false;
    if (args.has("--no-dp")) config.dead_pocket.enabled = false;
    const std::string out = args.required("--out");
    const bool overwrite = args.has("--force");
    if (!overwrite && fs::exists(out + "/report.json"))
      throw InputError(out, "holds a finished run already (pass --force to overwrite)");
    fs::create_directories(out);

    auto map = quake3::loadQuake3Map(config.world.map, config.world.patch_level);
    quake3::Quake3World world(map, config);
    Episode episode(world, makeSlam(config.slam.backend, world.intrinsics(), config), config);

    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    std::ofstream decisions(out + "/decisions.jsonl");
    episode.runUntilDone(
        [&](const StepRecord& r) {
          decisions << toJson(r).dump() << '\n' << std::flush;
          std::cerr << "step " << r.step << ": "
                    << (r.chosen >= 0 ? r.candidates[r.chosen].verdict.candidate : std::string("stall"))
                    << (r.rewind ? " + rewind" : "") << " (" << r.wall_seconds << " s)\n";
        },
        &g_stop);

    nlohmann::json report = {{"tool", "valerant_explore"}, {"map", config.world.map}, {"spawn", config.world.spawn},
                             {"slam", config.slam.backend}, {"policy", config.policy.kind}, {"seed", config.world.seed},
                             {"budget", config.policy.budget_steps}, {"interrupted", g_stop.load()},
                             {"rf", config.floor.enabled}, {"col_pc", config.collision.pointcloud_enabled},
                             {"col_depth", config.collision.depth_enabled}, {"dp", config.dead_pocket.enabled}};
    writeOutputs(episode, world, out, overwrite, report);
    report.erase("files");
    std::cout << report.dump() << std::endl;
    return g_stop ? 130 : 0;
  } catch (const std::exception& e) {
    std::cerr << "valerant_explore: error: " << e.what() << std::endl;
    return 1;
  }
}
