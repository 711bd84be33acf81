// valerant_bench render: frames/s of colour + depth rendering along committed candidate
// rollouts (uw, jq, lw, ... in turn), plus the process's peak resident memory.
#include <sys/resource.h>

#include <chrono>
#include <memory>

#include "../tool_config.h"
#include "bench.h"
#include "valerant/world/quake3/quake3_world.h"

namespace valerant::tools {

double peakResidentMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // Linux reports KiB
}

namespace {

nlohmann::json runRenderBench(const Config& config, long frames) {
  tools::requireEngineWorld(config, "valerant_bench render");
  const auto load_start = std::chrono::steady_clock::now();
  auto map = quake3::loadQuake3Map(config.world.map, config.world.patch_level);
  quake3::Quake3World world(map, config);
  const double load_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - load_start).count();

  // A varied path: forward, rotations and turns in turn, each committed.
  const std::vector<std::string> cycle = {"uw", "jq", "lw", "lq", "jw"};
  long rendered = 0;
  const auto start = std::chrono::steady_clock::now();
  for (size_t i = 0; rendered < frames; ++i) {
    ActionSequence seq = makeActionSequence(cycle[i % cycle.size()], config);
    if (static_cast<long>(seq.steps.size()) > frames - rendered) seq.steps.resize(frames - rendered);
    const Rollout r = world.rollout(seq);
    world.commit(r);
    rendered += static_cast<long>(r.frames.size());
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return {{"bench", "render"},
          {"map", config.world.map},
          {"width", config.world.width},
          {"height", config.world.height},
          {"frames", rendered},
          {"seconds", seconds},
          {"load_seconds", load_s},
          {"frames_per_second", rendered / seconds},
          {"peak_rss_mib", peakResidentMiB()}};
}

}  // namespace

BenchRun addBenchRender(CLI::App& bench) {
  CLI::App* app = bench.add_subcommand("render",
                                       "frames/s of colour + depth rendering along committed rollouts, "
                                       "peak memory");
  auto tool_config = std::make_shared<ToolConfig>(*app);
  tool_config->keyFlag("--map", "world.map", "MAP", "map name or PK3:MAP");
  tool_config->keyFlag("--spawn", "world.spawn", "INT", "spawn point index");
  auto frames = std::make_shared<long>(1000);
  addInteger(*app, "--frames", *frames, "frames to render", 1L);
  return [tool_config, frames] { return runRenderBench(tool_config->document().parse(), *frames); };
}

}  // namespace valerant::tools
