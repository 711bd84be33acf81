// valerant_bench graph: the cost of the ROS node graph over the in-process episode.
// Runs one episode with valerant_explore, then the same map, spawn, seed, SLAM, budget
// and configuration through `roslaunch valerant explore.launch` on a private ROS
// master, and reports
//   episode_ratio  graph / in-process episode wall time (report.json wall_seconds: the
//                  branch-evaluate-commit loop, what the graph's messaging slows down)
//   process_ratio  graph / in-process wall time of the whole command, including the
//                  master, node start-up and map loading in every node
// and whether both made the same decisions (decisions.jsonl without timings).
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "../child_process.h"
#include "../cli_args.h"
#include "bench.h"
#include "valerant/config/config.h"

namespace valerant::tools {
namespace {

namespace fs = std::filesystem;

struct EpisodeRun {
  double process_seconds = 0;
  double episode_seconds = 0;
  nlohmann::json decisions = nlohmann::json::array();
};

// Runs `argv` with logs in `dir`, then reads the episode it wrote into `dir`.
EpisodeRun runEpisode(const std::vector<std::string>& argv, const std::string& dir,
                      const std::map<std::string, std::string>& environment = {}) {
  fs::create_directories(dir);
  const auto start = std::chrono::steady_clock::now();
  const bool ok = waitForChild(startChild(argv, dir + "/stdout.log", dir + "/stderr.log", environment));
  EpisodeRun run;
  run.process_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!ok) throw InputError(argv[0], "failed (see " + dir + "/stderr.log and stdout.log)");
  std::ifstream report_file(dir + "/report.json");
  if (!report_file) throw InputError(dir + "/report.json", "missing after " + argv[0]);
  const nlohmann::json report = nlohmann::json::parse(report_file);
  run.episode_seconds = report.at("wall_seconds").get<double>();
  std::ifstream decisions(dir + "/decisions.jsonl");
  for (std::string line; std::getline(decisions, line);) {
    nlohmann::json record = nlohmann::json::parse(line);
    record.erase("seconds");  // wall-clock timings always differ
    record.erase("wall_seconds");
    run.decisions.push_back(record);
  }
  return run;
}

}  // namespace

nlohmann::json benchGraph(int argc, char** argv) {
  CliArgs args(argc, argv, {"--map", "--spawn", "--seed", "--slam", "--budget", "--config", "--out"});
  const std::string config_file = fs::absolute(args.get("--config", defaultConfigPath())).string();
  const Config config = loadConfig(config_file);
  const std::string map = args.get("--map", config.world.map);
  const std::string spawn = std::to_string(args.integer("--spawn", config.world.spawn));
  const std::string seed = std::to_string(args.integer("--seed", 0));
  const std::string slam = args.get("--slam", config.slam.backend);
  const std::string budget = std::to_string(args.integer("--budget", 5));
  const std::string out = fs::absolute(args.required("--out")).string();
  const std::string explore = siblingTool("valerant_explore");

  const EpisodeRun in_process =
      runEpisode({explore, "--map", map, "--spawn", spawn, "--seed", seed, "--slam", slam, "--budget", budget,
                  "--config", config_file, "--force", "--out", out + "/in_process"},
                 out + "/in_process");
  // A private master on its own port, so a running ROS system is not disturbed.
  const std::string port = std::to_string(20000 + getpid() % 20000);
  const EpisodeRun graph = runEpisode(
      {"roslaunch", "-p", port, "valerant", "explore.launch", "map:=" + map, "spawn:=" + spawn, "seed:=" + seed,
       "slam:=" + slam, "budget:=" + budget, "config_file:=" + config_file,
       "width:=" + std::to_string(config.world.width), "height:=" + std::to_string(config.world.height),
       "output_dir:=" + out + "/graph"},
      out + "/graph", {{"ROS_MASTER_URI", "http://localhost:" + port}});

  return {{"bench", "graph"},
          {"map", map},
          {"spawn", std::stoi(spawn)},
          {"slam", slam},
          {"budget", std::stoi(budget)},
          {"committed_steps", in_process.decisions.size()},
          {"in_process_episode_s", in_process.episode_seconds},
          {"graph_episode_s", graph.episode_seconds},
          {"episode_ratio", graph.episode_seconds / in_process.episode_seconds},
          {"in_process_process_s", in_process.process_seconds},
          {"graph_process_s", graph.process_seconds},
          {"process_ratio", graph.process_seconds / in_process.process_seconds},
          {"same_decisions", graph.decisions == in_process.decisions},
          {"out", out}};
}

}  // namespace valerant::tools
