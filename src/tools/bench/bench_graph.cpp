// valerant_bench graph: the cost of the ROS node graph over the in-process episode.
// Runs one episode with valerant_explore, then the same map, spawn, seed, SLAM, budget
// and configuration through `roslaunch valerant explore.launch` on a private ROS
// master, and reports
//   episode_ratio  graph / in-process episode wall time (report.json wall_seconds: the
//                  branch-evaluate-commit loop, what the graph's messaging slows down)
//   process_ratio  graph / in-process wall time of the whole command, including the
//                  master, node start-up and map loading in every node
// and whether both made the same decisions (decisions.jsonl without timings). Both runs
// read the configuration the command line makes (--config, the flags, --set), written to
// OUT/config.yaml, with the launch arguments that would override it set from it.
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "../child_process.h"
#include "../tool_config.h"
#include "bench.h"
#include "valerant/common/output_file.h"
#include "valerant/config/config.h"

namespace valerant::tools {
namespace {

namespace fs = std::filesystem;

struct EpisodeRun {
  double process_seconds = 0;
  double episode_seconds = 0;
  nlohmann::json decisions = nlohmann::json::array();
};

// The last non-empty line of the log at `path` ("" when there is none): a failed
// tool's own error.
std::string lastLogLine(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

// Runs `argv` with logs in `dir`, then reads the episode it wrote into `dir`.
EpisodeRun runEpisode(const std::vector<std::string>& argv, const std::string& dir,
                      const std::map<std::string, std::string>& environment = {}) {
  fs::create_directories(dir);
  const auto start = std::chrono::steady_clock::now();
  const bool ok = waitForChild(startChild(argv, dir + "/stdout.log", dir + "/stderr.log", environment));
  EpisodeRun run;
  run.process_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!ok) {  // its error (a map not found, say) in the message, not only in the log
    const std::string error = lastLogLine(dir + "/stderr.log");
    throw InputError(argv[0], "failed" + (error.empty() ? "" : ": " + error) + " (see " + dir +
                                  "/stderr.log and stdout.log)");
  }
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

std::string boolText(bool value) { return value ? "true" : "false"; }

nlohmann::json runGraphBench(const ConfigDocument& document, const std::string& out_flag) {
  const Config config = document.parse();
  const std::string out = fs::absolute(out_flag).string();
  fs::create_directories(out);
  const std::string config_file = out + "/config.yaml";
  writeFileAtomically(config_file, document.yaml());
  const std::string map = config.world.map, slam = config.slam.backend;
  const std::string spawn = std::to_string(config.world.spawn), seed = std::to_string(config.world.seed),
                    budget = std::to_string(config.policy.budget_steps);
  const std::string explore = siblingTool("valerant_explore");

  const EpisodeRun in_process =
      runEpisode({explore, "--config", config_file, "--force", "--out", out + "/in_process"}, out + "/in_process");
  // A private master on its own port, so a running ROS system is not disturbed.
  const std::string port = std::to_string(20000 + getpid() % 20000);
  const EpisodeRun graph =
      runEpisode({"roslaunch", "-p", port, "valerant", "explore.launch", "config_file:=" + config_file, "map:=" + map,
                  "spawn:=" + spawn, "seed:=" + seed, "slam:=" + slam, "budget:=" + budget,
                  "width:=" + std::to_string(config.world.width), "height:=" + std::to_string(config.world.height),
                  "policy:=" + config.policy.kind, "rf:=" + boolText(config.floor.enabled),
                  "col_pc:=" + boolText(config.collision.pointcloud_enabled),
                  "col_depth:=" + boolText(config.collision.depth_enabled),
                  "dp:=" + boolText(config.dead_pocket.enabled), "output_dir:=" + out + "/graph"},
                 out + "/graph", {{"ROS_MASTER_URI", "http://localhost:" + port}});

  return {{"bench", "graph"},
          {"map", map},
          {"spawn", config.world.spawn},
          {"slam", slam},
          {"budget", config.policy.budget_steps},
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

}  // namespace

BenchRun addBenchGraph(CLI::App& bench) {
  CLI::App* app = bench.add_subcommand("graph",
                                       "one episode in process and through the ROS node graph: wall-time "
                                       "ratio and whether the decisions agree");
  auto tool_config = std::make_shared<ToolConfig>(*app);
  tool_config->keyFlag("--map", "world.map", "MAP", "map name or PK3:MAP");
  tool_config->keyFlag("--spawn", "world.spawn", "INT", "spawn point index");
  tool_config->keyFlag("--seed", "world.seed", "INT", "random seed", "0");
  tool_config->keyFlag("--slam", "slam.backend", "visual|oracle", "SLAM backend");
  tool_config->keyFlag("--budget", "policy.budget_steps", "INT", "steps to commit", "5");
  auto out = std::make_shared<std::string>();
  addPath(*app, "--out", *out, "output folder (config.yaml, in_process/, graph/)", "DIR")->required();
  return [tool_config, out] { return runGraphBench(tool_config->document(), *out); };
}

}  // namespace valerant::tools
