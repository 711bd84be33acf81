// valerant_explore: one exploration episode on the engine world, without ROS.
//
//   valerant_explore --map NAME [--spawn I] [--slam visual|oracle] [--budget N]
//                    [--no-rf] [--no-col-pc] [--no-col-depth] [--no-dp] [--seed S]
//                    [--policy valerant|random|forward|frontier]
//                    [--config FILE] [--set key=value ...] [--force | --resume] --out DIR
//
// Writes every export format (map/run_exports.h: map.ply, map.pcd, map.bt, grid.pgm +
// grid.yaml, mesh.obj, mesh.glb, walkable.json, overview.png, orbit.png), the map kept
// for valerant_export (map/run_map.h: keyframes.pcd, keyframes.txt, config.yaml),
// trajectory.txt (TUM, SLAM frame), gt_trajectory.txt (TUM, BSP frame, game units),
// decisions.jsonl, topdown.png and, last, report.json into DIR; prints one JSON summary
// line. After every step that changes the map, DIR/snapshot holds the map of the
// committed steps. A folder holding a run is an error unless --force (replace it) or,
// for an unfinished run, --resume (eval/run_directory.h). The flags that stand for
// configuration keys go through the configuration's checks (tools/tool_config.h).
// Ctrl-C (or SIGTERM) stops after the current step and still writes everything, then
// exits 130 (143); a second signal ends the process at once, leaving an unfinished run.
#include <atomic>
#include <csignal>
#include <iostream>

#include "cli_args.h"
#include "tool_config.h"
#include "valerant/common/joined.h"
#include "valerant/common/output_file.h"
#include "valerant/eval/episode_outputs.h"
#include "valerant/eval/run_directory.h"
#include "valerant/explore/episode.h"
#include "valerant/explore/episode_json.h"
#include "valerant/map/run_map.h"
#include "valerant/world/quake3/quake3_world.h"

using namespace valerant;
namespace fs = std::filesystem;

namespace {

std::atomic<bool> g_stop{false};
std::atomic<int> g_signal{0};

// The first signal asks the episode to stop after its step; a second one ends the
// process the usual way (what is on disk is whole: every file is written atomically).
void onSignal(int signal) {
  if (g_stop.exchange(true)) {
    std::signal(signal, SIG_DFL);
    std::raise(signal);
    return;
  }
  g_signal = signal;
}

const std::vector<tools::FlagKey> kFlagKeys = {{"--map", "world.map"},         {"--spawn", "world.spawn"},
                                               {"--seed", "world.seed"},       {"--slam", "slam.backend"},
                                               {"--policy", "policy.kind"},    {"--budget", "policy.budget_steps"}};
const std::vector<tools::SwitchKey> kSwitchKeys = {{"--no-rf", "floor.enabled=false"},
                                                   {"--no-col-pc", "collision.pointcloud_enabled=false"},
                                                   {"--no-col-depth", "collision.depth_enabled=false"},
                                                   {"--no-dp", "dead_pocket.enabled=false"}};

// A resumed run takes its own configuration: a flag that would change it is an error.
void requireNoConfigFlags(const tools::CliArgs& args) {
  std::vector<std::string> given;
  for (const auto& f : kFlagKeys)
    if (args.has(f.flag)) given.push_back(f.flag);
  for (const auto& f : kSwitchKeys)
    if (args.has(f.flag)) given.push_back(f.flag);
  if (args.has("--config")) given.push_back("--config");
  if (!args.sets().empty()) given.push_back("--set");
  if (!given.empty())
    throw InputError("--resume", "takes the run's own configuration (its config.yaml); leave out " + joined(given));
}

}  // namespace

int main(int argc, char** argv) {
  try {
    tools::CliArgs args(argc, argv, {"--map", "--spawn", "--slam", "--budget", "--seed", "--config", "--out", "--policy", "--set"},
                        {"--no-rf", "--no-col-pc", "--no-col-depth", "--no-dp", "--force", "--resume"});
    const std::string out = args.required("--out");
    if (args.has("--force") && args.has("--resume")) throw InputError("--force, --resume", "choose one");
    const RunStart start = args.has("--resume") ? RunStart::kResume
                           : args.has("--force") ? RunStart::kForce
                                                 : RunStart::kNew;
    if (start == RunStart::kResume) requireNoConfigFlags(args);
    // Everything is checked before the folder is touched.
    const ConfigDocument document = start == RunStart::kResume ? ConfigDocument::load(out + "/config.yaml")
                                                               : tools::toolConfigDocument(args, kFlagKeys, kSwitchKeys);
    const Config config = document.parse();
    prepareRunDirectory(out, start);
    std::vector<nlohmann::json> recorded;
    if (start == RunStart::kResume) {
      recorded = recordedDecisions(out);
      std::cerr << "valerant_explore: resuming " << out << ": replaying " << recorded.size()
                << " recorded steps, then going on\n";
    } else {
      saveRunConfig(out, document, false);
    }

    auto map = quake3::loadQuake3Map(config.world.map, config.world.patch_level);
    quake3::Quake3World world(map, config);
    Episode episode(world, config);

    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    nlohmann::json report = runReportHeader("valerant_explore", config);
    AppendOnlyLog decisions(out + "/decisions.jsonl", start == RunStart::kResume);
    episode.runUntilDone(
        [&](const StepRecord& r) {
          const nlohmann::json decision = toJson(r);
          const size_t index = static_cast<size_t>(r.step) - 1;
          if (index < recorded.size()) {
            requireSameDecision(out, recorded[index], decision);
          } else {
            decisions.writeLine(decision.dump());
          }
          snapshotAfterStep(out, episode, r, report);
          std::cerr << "step " << r.step << ": "
                    << (r.chosen >= 0 ? r.candidates[r.chosen].verdict.candidate : std::string("stall"))
                    << (r.rewind ? " + rewind" : "") << (index < recorded.size() ? " (as recorded)" : "") << " ("
                    << r.wall_seconds << " s)\n";
        },
        &g_stop);
    if (episode.history().size() < recorded.size())
      throw InputError(out + "/decisions.jsonl", "records " + std::to_string(recorded.size()) +
                                                     " steps, but the resumed episode ended after " +
                                                     std::to_string(episode.history().size()));

    writeEpisodeOutputs(episode, &world.map(), out, true, report);
    // A signal during the writes above still counts: the report says what the exit status says.
    const int signal = g_signal.load();
    report["interrupted"] = signal != 0;
    if (signal) report["signal"] = signal == SIGINT ? "SIGINT" : "SIGTERM";
    if (start == RunStart::kResume) report["resumed_after_steps"] = recorded.size();
    writeRunReport(out, report);
    report.erase("files");
    std::cout << report.dump() << std::endl;
    return signal ? 128 + signal : 0;
  } catch (const std::exception& e) {
    std::cerr << "valerant_explore: error: " << e.what() << std::endl;
    return 1;
  }
}
