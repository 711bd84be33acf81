// valerant_bench slam: frames/s of one SLAM branch per candidate on one core (the
// process pins itself to one CPU, OpenCV and Ceres run single-threaded), including
// per-frame depth, and the cost of snapshot() + restore() of a branch that has tracked
// its whole rollout. Rendering is done before timing starts.
#include <sched.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <opencv2/core.hpp>

#include "../thread_clock.h"
#include "../tool_config.h"
#include "bench.h"
#include "valerant/slam/rollout_truth.h"
#include "valerant/slam/slam_factory.h"
#include "valerant/world/quake3/quake3_world.h"

namespace valerant::tools {
namespace {

nlohmann::json runSlamBench(const Config& config, const std::string& candidate_list, long repeats) {
  tools::requireEngineWorld(config, "valerant_bench slam");
  const std::string backend = config.slam.backend;
  std::vector<ActionSequence> sequences;  // validated before the map is loaded
  checkFlagValues([&] {
    for (const auto& c : commaList("--candidates", candidate_list)) sequences.push_back(makeActionSequence(c, config));
  });
  const int cpu = pinToOneCpu();
  cv::setNumThreads(1);

  auto map = quake3::loadQuake3Map(config.world.map, config.world.patch_level);
  quake3::Quake3World world(map, config);
  const auto truth = std::make_shared<RolloutTruth>();  // read by the oracle backend
  auto slam = makeSlam(backend, world.intrinsics(), config, truth);
  const Rollout context = world.context();
  const CheckpointId start = world.checkpoint();
  std::vector<Rollout> rollouts;
  for (const auto& seq : sequences) {
    world.restore(start);
    rollouts.push_back(world.rollout(seq));
  }
  auto track = [&truth](Slam& s, const Rollout& r) {
    const RolloutTruth::Hold held = truth->hold(r);
    for (size_t i = 0; i < r.frames.size(); ++i) s.track(SlamInput{r.frames[i], {r.id, static_cast<int>(i)}});
  };
  track(*slam, context);

  constexpr int kSnapshotRepeats = 200;
  nlohmann::json candidates = nlohmann::json::array();
  double total_frames = 0, total_cpu = 0, total_wall = 0, worst_snapshot_restore_ms = 0;
  double min_fps_cpu = std::numeric_limits<double>::infinity();
  for (size_t c = 0; c < sequences.size(); ++c) {
    // Every repeat branches from the same committed state, as the explorer does.
    ThreadClock spent;
    std::unique_ptr<Slam> branch;
    for (long r = 0; r < repeats; ++r) {
      const auto t0 = ThreadClock::now();
      branch = slam->branch();
      track(*branch, rollouts[c]);
      spent += ThreadClock::now() - t0;
    }
    const double frames = static_cast<double>(rollouts[c].frames.size() * repeats);
    // snapshot() + restore() of the branch at its largest state (whole rollout tracked).
    double max_ms = 0;
    const auto s0 = ThreadClock::now();
    for (int i = 0; i < kSnapshotRepeats; ++i) {
      const auto one = ThreadClock::now();
      branch->restore(branch->snapshot());
      max_ms = std::max(max_ms, 1e3 * (ThreadClock::now() - one).wall);
    }
    const double mean_ms = 1e3 * (ThreadClock::now() - s0).wall / kSnapshotRepeats;
    worst_snapshot_restore_ms = std::max(worst_snapshot_restore_ms, max_ms);
    total_frames += frames, total_cpu += spent.cpu, total_wall += spent.wall;
    min_fps_cpu = std::min(min_fps_cpu, frames / spent.cpu);
    candidates.push_back({{"candidate", sequences[c].name},
                          {"frames", rollouts[c].frames.size()},
                          {"keyframes", branch->keyframeCount()},
                          {"fps_cpu", frames / spent.cpu},
                          {"fps_wall", frames / spent.wall},
                          {"snapshot_restore_ms_mean", mean_ms},
                          {"snapshot_restore_ms_max", max_ms}});
  }
  return {{"bench", "slam"},
          {"slam", backend},
          {"map", config.world.map},
          {"spawn", config.world.spawn},
          {"width", config.world.width},
          {"height", config.world.height},
          {"cpu", cpu},
          {"repeats", repeats},
          {"fps_cpu", total_frames / total_cpu},
          {"fps_wall", total_frames / total_wall},
          {"min_candidate_fps_cpu", min_fps_cpu},
          {"snapshot_restore_ms_max", worst_snapshot_restore_ms},
          {"candidates", candidates},
          {"peak_rss_mib", peakResidentMiB()}};
}

}  // namespace

int pinToOneCpu() {
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  if (sched_getaffinity(0, sizeof(allowed), &allowed) != 0) return -1;
  for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu) {
    if (!CPU_ISSET(cpu, &allowed)) continue;
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cpu, &one);
    return sched_setaffinity(0, sizeof(one), &one) == 0 ? cpu : -1;
  }
  return -1;
}

BenchRun addBenchSlam(CLI::App& bench) {
  CLI::App* app = bench.add_subcommand("slam",
                                       "SLAM frames/s per branch on one core and the cost of snapshot + "
                                       "restore");
  auto tool_config = std::make_shared<ToolConfig>(*app);
  tool_config->keyFlag("--map", "world.map", "MAP", "map name or PK3:MAP");
  tool_config->keyFlag("--spawn", "world.spawn", "INT", "spawn point index");
  tool_config->keyFlag("--slam", "slam.backend", "visual|oracle", "SLAM backend");
  auto candidates = std::make_shared<std::string>("uw,jw,lw,jq,lq");
  auto repeats = std::make_shared<long>(3);
  app->add_option("--candidates", *candidates, "candidates or key strings, comma-separated")
      ->type_name("LIST")
      ->capture_default_str();
  addInteger(*app, "--repeats", *repeats, "times each candidate is tracked", 1L);
  return [tool_config, candidates, repeats] {
    return runSlamBench(tool_config->document().parse(), *candidates, *repeats);
  };
}

}  // namespace valerant::tools
