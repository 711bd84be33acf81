// valerant_explore: one exploration episode on the engine or the learned world, without ROS.
//
//   valerant_explore --map NAME [--spawn I] [--image FILE] [--slam visual|oracle] [--budget N]
//                    [--no-rf] [--no-col-pc] [--no-col-depth] [--no-dp] [--seed S]
//                    [--policy valerant|random|forward|frontier]
//                    [--config FILE] [--set key=value ...] [--force | --resume] --out DIR
//                    (--help: every flag)
//
// Writes every export format (map/run_exports.h: map.ply, map.pcd, map.bt, grid.pgm +
// grid.yaml, mesh.obj, mesh.glb, walkable.json, overview.png, orbit.png), the map kept
// for valerant_export (map/run_map.h: keyframes.pcd, keyframes.txt, config.yaml),
// trajectory.txt (TUM, SLAM frame), gt_trajectory.txt (TUM, BSP frame, game units),
// decisions.jsonl, topdown.png and, last, report.json into DIR; prints one JSON summary
// line. After a step that changes the map, DIR/snapshot holds the map of the committed
// steps (on long runs not after every step: eval/snapshot_schedule.h). After every
// step, one progress line on stderr (explore/progress_line.h): step, committed steps,
// the candidate, the reachable floor observed, keyframes, resident memory and seconds.
// --image FILE starts the learned world (world.backend learned) from that screenshot: no
// level, so no ground truth (report.json's ground_truth is null, no gt_trajectory.txt);
// the screenshot is kept as DIR/screenshot.png for --resume. Without --image the learned
// world starts at the engine spawn, which also gives the ground truth.
// A folder holding a run is an error unless --force (replace it) or, for an unfinished
// run, --resume (eval/run_directory.h). The flags that stand for
// configuration keys go through the configuration's checks (tools/tool_config.h).
// Ctrl-C (or SIGTERM) stops after the current step and still writes everything, then
// exits 130 (143); a second signal ends the process at once, leaving an unfinished run.
#include <atomic>
#include <chrono>
#include <csignal>
#include <iostream>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "tool_config.h"
#include "valerant/common/joined.h"
#include "valerant/common/output_file.h"
#include "valerant/common/resident_memory.h"
#include "valerant/eval/episode_outputs.h"
#include "valerant/eval/live_coverage.h"
#include "valerant/eval/run_directory.h"
#include "valerant/explore/episode.h"
#include "valerant/explore/episode_json.h"
#include "valerant/explore/progress_line.h"
#include "valerant/map/run_map.h"
#include "valerant/world/learned/learned_world.h"
#include "valerant/world/quake3/reachable_floor.h"
#include "valerant/world/world_factory.h"

using namespace valerant;
namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;
double secondsBetween(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double>(to - from).count();
}

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

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "One exploration episode on the engine world, without ROS: the map in every export format, "
      "decisions, trajectories and report.json.",
      "valerant_explore"};
  tools::useToolConventions(app);
  tools::ToolConfig tool_config(app);
  tool_config.keyFlag("--map", "world.map", "MAP", "map name or PK3:MAP");
  tool_config.keyFlag("--spawn", "world.spawn", "INT", "spawn point index");
  tool_config.keyFlag("--seed", "world.seed", "INT", "random seed");
  tool_config.keyFlag("--slam", "slam.backend", "visual|oracle", "SLAM backend");
  tool_config.keyFlag("--policy", "policy.kind", "valerant|random|forward|frontier", "policy");
  tool_config.keyFlag("--budget", "policy.budget_steps", "INT", "steps to commit");
  tool_config.switchFlag("--no-rf", "floor.enabled=false", "ablation: no floor estimate");
  tool_config.switchFlag("--no-col-pc", "collision.pointcloud_enabled=false",
                         "ablation: no point-cloud collision check");
  tool_config.switchFlag("--no-col-depth", "collision.depth_enabled=false", "ablation: no depth collision check");
  tool_config.switchFlag("--no-dp", "dead_pocket.enabled=false", "ablation: no dead-pocket rewind");
  std::string image;
  tools::addPath(app, "--image", image,
                 "start the learned world from this screenshot (PNG, JPEG; needs world.backend learned)",
                 "FILE");
  std::string out;
  tools::addPath(app, "--out", out, "run folder", "DIR")->required();
  CLI::Option* force = app.add_flag("--force", "replace the run the folder holds");
  CLI::Option* resume =
      app.add_flag("--resume", "continue the unfinished run the folder holds, with its own configuration");
  force->excludes(resume);
  return tools::runTool(app, argc, argv, [&] {
    const RunStart start = resume->count() ? RunStart::kResume : force->count() ? RunStart::kForce : RunStart::kNew;
    // A resumed run takes its own configuration: a flag that would change it is an error.
    if (start == RunStart::kResume && !tool_config.givenFlags().empty())
      throw tools::UsageError("--resume", "takes the run's own configuration (its config.yaml); leave out " +
                                              joined(tool_config.givenFlags()));
    // Everything is checked before the folder is touched.
    const ConfigDocument document =
        start == RunStart::kResume ? ConfigDocument::load(out + "/config.yaml") : tool_config.document();
    const Config config = document.parse();
    if (!image.empty() && start == RunStart::kResume)
      throw tools::UsageError("--image", "--resume starts from the run's own screenshot.png; leave out --image");
    if (!image.empty() && config.world.backend != "learned")
      throw tools::UsageError("--image " + image, "starts the learned world only: add --set world.backend=learned");
    if (!image.empty() && config.slam.backend == "oracle")
      throw tools::UsageError("--image " + image, "has no ground truth for the oracle SLAM: use --slam visual");
    const std::string kept_screenshot = out + "/screenshot.png";
    const std::string screenshot =
        start == RunStart::kResume ? (fs::exists(kept_screenshot) ? kept_screenshot : "") : image;
    // The engine map: the world itself, or the learned world's truth shadow; none from a screenshot.
    std::shared_ptr<const quake3::Quake3Map> map;
    const std::unique_ptr<WorldModel> world = makeWorld(config, screenshot, map);
    // Read before the folder is prepared: --force may remove a screenshot kept inside it.
    const cv::Mat screenshot_rgb = screenshot.empty() ? cv::Mat() : readScreenshot(screenshot);
    prepareRunDirectory(out, start);
    std::vector<nlohmann::json> recorded;
    if (start == RunStart::kResume) {
      recorded = recordedDecisions(out);
      std::cerr << "valerant_explore: resuming " << out << ": replaying " << recorded.size()
                << " recorded steps, then going on\n";
    } else {
      saveRunConfig(out, document, false);
      if (!screenshot_rgb.empty()) {  // as PNG: a resumed run decodes the same pixels
        cv::Mat bgr;
        cv::cvtColor(screenshot_rgb, bgr, cv::COLOR_RGB2BGR);
        writeImageAtomically(kept_screenshot, bgr);
      }
    }

    Episode episode(*world, config);
    // The progress lines' coverage (report.json's is counted again at the end).
    std::optional<LiveCoverage> coverage;
    if (map)
      coverage.emplace(quake3::floodFillReachableFloor(*map->collision,
                                                       map->bsp.spawnPoints().at(config.world.spawn).origin));
    const auto episode_start = Clock::now();
    auto last_line = episode_start;
    SnapshotSchedule snapshots;
    RunSnapshot snapshot(out);
    double snapshot_seconds = 0;  // writing the map snapshots: outside the steps' own timings

    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    nlohmann::json report = runReportHeader("valerant_explore", config);
    if (!screenshot.empty()) {  // no level: the configuration's map and spawn were not used
      report["screenshot"] = screenshot;
      report["map"] = nullptr;
      report["spawn"] = nullptr;
    }
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
          snapshot_seconds += snapshotAfterStep(snapshot, episode, r, report, snapshots);
          StepProgress progress;
          if (coverage) progress.observed_percent = coverage->update(episode);
          progress.resident_bytes = residentMemory().current_bytes;
          const auto now = Clock::now();
          progress.seconds = secondsBetween(last_line, now);
          progress.total_seconds = secondsBetween(episode_start, now);
          progress.as_recorded = index < recorded.size();
          last_line = now;
          std::cerr << progressLine(r, progress) << '\n';
        },
        &g_stop);
    if (episode.history().size() < recorded.size())
      throw InputError(out + "/decisions.jsonl", "records " + std::to_string(recorded.size()) +
                                                     " steps, but the resumed episode ended after " +
                                                     std::to_string(episode.history().size()));

    const auto outputs_start = Clock::now();
    writeEpisodeOutputs(episode, map.get(), out, true, report);
    report["output_seconds"] = secondsBetween(outputs_start, Clock::now());  // exports and ground truth
    // A signal during the writes above still counts: the report says what the exit status says.
    const int signal = g_signal.load();
    report["interrupted"] = signal != 0;
    if (signal) report["signal"] = signal == SIGINT ? "SIGINT" : "SIGTERM";
    if (start == RunStart::kResume) report["resumed_after_steps"] = recorded.size();
    report["snapshot_seconds"] = snapshot_seconds;
    report["peak_resident_bytes"] = residentMemory().peak_bytes;
    writeRunReport(out, report);
    report.erase("files");
    std::cout << report.dump() << std::endl;
    return signal ? 128 + signal : 0;
  });
}
