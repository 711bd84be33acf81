// valerant_explore: one exploration episode on the engine world, without ROS.
//
//   valerant_explore --map NAME [--spawn I] [--slam visual|oracle] [--budget N]
//                    [--no-rf] [--no-col-pc] [--no-col-depth] [--no-dp] [--seed S]
//                    [--policy valerant|random|forward|frontier]
//                    [--config FILE] [--force] --out DIR
//
// Writes every export format (map/run_exports.h: map.ply, map.pcd, map.bt, grid.pgm +
// grid.yaml, mesh.obj, mesh.glb, walkable.json, overview.png, orbit.png), the map kept
// for valerant_export (map/run_map.h: keyframes.pcd, keyframes.txt, config.yaml),
// trajectory.txt (TUM, SLAM frame), gt_trajectory.txt (TUM, BSP frame, game units),
// decisions.jsonl, topdown.png and report.json into DIR; prints one JSON summary line.
// Ctrl-C stops after the current step and still writes everything.
#include <atomic>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "cli_args.h"
#include "valerant/eval/episode_outputs.h"
#include "valerant/explore/episode.h"
#include "valerant/explore/episode_json.h"
#include "valerant/map/run_map.h"
#include "valerant/slam/slam_factory.h"
#include "valerant/world/quake3/quake3_world.h"

using namespace valerant;
namespace fs = std::filesystem;

namespace {

std::atomic<bool> g_stop{false};
void onSignal(int) { g_stop = true; }

}  // namespace

int main(int argc, char** argv) {
  try {
    tools::CliArgs args(argc, argv, {"--map", "--spawn", "--slam", "--budget", "--seed", "--config", "--out", "--policy"},
                        {"--no-rf", "--no-col-pc", "--no-col-depth", "--no-dp", "--force"});
    const std::string config_path = args.get("--config", defaultConfigPath());
    Config config = loadConfig(config_path);
    config.world.map = args.get("--map", config.world.map);
    config.world.spawn = args.integer("--spawn", config.world.spawn);
    config.world.seed = args.integer("--seed", config.world.seed);
    config.slam.backend = args.get("--slam", config.slam.backend);
    config.policy.kind = args.get("--policy", config.policy.kind);
    if (config.policy.kind != "valerant" && config.policy.kind != "random" && config.policy.kind != "forward" &&
        config.policy.kind != "frontier")
      throw InputError("--policy " + config.policy.kind, "unknown (known: valerant, random, forward, frontier)");
    config.policy.budget_steps = args.integer("--budget", config.policy.budget_steps);
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
    saveRunConfig(out, config_path, overwrite);

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
    writeEpisodeOutputs(episode, &world.map(), out, overwrite, report);
    report.erase("files");
    std::cout << report.dump() << std::endl;
    return g_stop ? 130 : 0;
  } catch (const std::exception& e) {
    std::cerr << "valerant_explore: error: " << e.what() << std::endl;
    return 1;
  }
}
