// valerant_bench sweep: milliseconds of one plane sweep (the visual SLAM's dense depth,
// plane_sweep.h) on one core with slam.visual.sweep.simd off and on (sweep_kernels.h),
// and whether they gave the same bits. The sweeps are those of engine frames: each
// frame of the candidates from --gap frames on, against the frames --gap and 2 x --gap
// before it, with the engine's poses (game units, nearest plane 8 units).
#include <opencv2/imgproc.hpp>

#include "../thread_clock.h"
#include "../tool_config.h"
#include "bench.h"
#include "valerant/slam/visual/pinhole.h"
#include "valerant/slam/visual/plane_sweep.h"
#include "valerant/world/quake3/quake3_world.h"

namespace valerant::tools {
namespace {

bool sameBits(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() &&
         std::equal(a.datastart, a.dataend, b.datastart);  // NaN compares by its bits here
}

struct SweepCase {
  visual::SweepView reference;
  std::vector<visual::SweepView> sources;
};

nlohmann::json runSweepBench(const Config& config, const std::string& candidate_list, long gap, long repeats) {
  tools::requireEngineWorld(config, "valerant_bench sweep");
  std::vector<ActionSequence> sequences;
  checkFlagValues([&] {
    for (const auto& c : commaList("--candidates", candidate_list)) sequences.push_back(makeActionSequence(c, config));
  });
  const int cpu = pinToOneCpu();
  cv::setNumThreads(1);
  const PlaneSweepParams& params = config.slam.visual.sweep;
  auto map = quake3::loadQuake3Map(config.world.map, config.world.patch_level);
  quake3::Quake3World world(map, config);
  const CameraIntrinsics k = visual::downsampled(world.intrinsics(), params.downsample);
  const CheckpointId start = world.checkpoint();
  std::vector<SweepCase> cases;
  for (const ActionSequence& seq : sequences) {
    world.restore(start);
    const Rollout r = world.rollout(seq);
    std::vector<visual::SweepView> views;
    for (size_t i = 0; i < r.frames.size(); ++i) {
      cv::Mat grey;
      cv::cvtColor(r.frames[i], grey, cv::COLOR_RGB2GRAY);
      views.push_back({visual::sweepImage(grey, params), r.truth.at(i).camera_to_world});
    }
    for (size_t i = 2 * gap; i < views.size(); ++i)
      cases.push_back({views[i], {views[i - gap], views[i - 2 * gap]}});
  }
  if (cases.empty()) throw InputError("--gap", "leaves no frame with two sources in the candidates' rollouts");

  constexpr double kNear = 8;  // game units
  // slam.visual.sweep.simd off, then on where this CPU has the AVX2 loops.
  std::vector<bool> simd = {false};
  if (visual::fastestSweepIsa() != visual::SweepIsa::kPortable) simd.push_back(true);
  nlohmann::json timings = nlohmann::json::object();
  std::vector<std::vector<visual::SweepDepth>> results(simd.size());
  for (size_t a = 0; a < simd.size(); ++a) {
    PlaneSweepParams p = params;
    p.simd = simd[a];
    ThreadClock spent;
    for (long rep = 0; rep < repeats; ++rep) {
      results[a].clear();
      const auto t0 = ThreadClock::now();
      for (const SweepCase& c : cases) results[a].push_back(visual::planeSweep(c.reference, c.sources, k, kNear, p));
      spent += ThreadClock::now() - t0;
    }
    const double sweeps = static_cast<double>(cases.size() * repeats);
    timings[simd[a] ? "avx2" : "portable"] = {{"ms_cpu", 1e3 * spent.cpu / sweeps},
                                                                         {"ms_wall", 1e3 * spent.wall / sweeps}};
  }
  bool identical = true;
  for (size_t a = 1; a < simd.size(); ++a)
    for (size_t i = 0; i < cases.size(); ++i)
      identical = identical && sameBits(results[0][i].depth, results[a][i].depth) &&
                  sameBits(results[0][i].confidence, results[a][i].confidence);
  nlohmann::json out = {{"bench", "sweep"},     {"map", config.world.map}, {"spawn", config.world.spawn},
                        {"cpu", cpu},           {"sweeps", cases.size()},  {"repeats", repeats},
                        {"sources", 2},         {"gap", gap},              {"width", k.width},
                        {"height", k.height},   {"isa", timings},          {"identical", identical}};
  if (timings.contains("avx2"))
    out["speedup_cpu"] = timings["portable"]["ms_cpu"].get<double>() / timings["avx2"]["ms_cpu"].get<double>();
  return out;
}

}  // namespace

BenchRun addBenchSweep(CLI::App& bench) {
  CLI::App* app = bench.add_subcommand("sweep", "plane-sweep milliseconds per frame on one core, per instruction set");
  auto tool_config = std::make_shared<ToolConfig>(*app);
  tool_config->keyFlag("--map", "world.map", "MAP", "map name or PK3:MAP");
  tool_config->keyFlag("--spawn", "world.spawn", "INT", "spawn point index");
  auto candidates = std::make_shared<std::string>("uw,jw,lw");
  auto gap = std::make_shared<long>(6);
  auto repeats = std::make_shared<long>(2);
  app->add_option("--candidates", *candidates, "candidates or key strings, comma-separated")
      ->type_name("LIST")
      ->capture_default_str();
  addInteger(*app, "--gap", *gap, "frames between a frame and its nearer source", 1L);
  addInteger(*app, "--repeats", *repeats, "times each sweep is run", 1L);
  return [tool_config, candidates, gap, repeats] {
    return runSweepBench(tool_config->document().parse(), *candidates, *gap, *repeats);
  };
}

}  // namespace valerant::tools
