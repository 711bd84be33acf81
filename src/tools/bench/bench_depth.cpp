// valerant_bench depth: accuracy and CPU cost of the learned depth prior against the
// engine's true depth, next to the visual SLAM's plane-sweep depth on the same frames.
// For each map and each of the first N spawns it renders the five paper candidates,
// tracks each with a visual SLAM branch from the spawn's context (as the explorer does)
// and scores every 4th frame of every candidate. Both depths are compared at the net's
// resolution (truth and plane-sweep depth downsampled with INTER_NEAREST), on pixels
// whose true depth is in [0.1, 80] m (sky, NaN, is left out), on frames whose camera
// is outside solid brushes (a rollout that walks into a wall sees its inside, which
// no depth estimate can judge, and training never shows), with the per-frame
// figures averaged over frames (learn/valerant_learn/metrics.py's protocol, which also
// clamps predictions into that range; this bench does not).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "../thread_clock.h"
#include "../tool_config.h"
#include "bench.h"
#include "valerant/config/package_dir.h"
#include "valerant/eval/metric_depth_score.h"
#include "valerant/common/depth_prior.h"
#include "valerant/slam/slam_factory.h"
#include "valerant/world/quake3/quake3_world.h"

namespace valerant::tools {
namespace {

constexpr size_t kFrameStride = 4;

bool hasDepth(float d) { return std::isfinite(d) && d > 0; }

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  auto middle = v.begin() + static_cast<long>(v.size() / 2);
  std::nth_element(v.begin(), middle, v.end());
  return *middle;
}

// Median of truth / estimate over the pixels where both exist (1 when none): the
// plane-sweep depth is in map units of an unknown scale, so each frame is aligned to
// metres by this ratio before scoring; the figures measure its shape, not its scale.
double medianScale(const cv::Mat& estimate, const cv::Mat& truth) {
  std::vector<double> ratios;
  for (int y = 0; y < truth.rows; ++y)
    for (int x = 0; x < truth.cols; ++x) {
      const float g = truth.at<float>(y, x), e = estimate.at<float>(y, x);
      if (scoredTruthDepth(g) && hasDepth(e)) ratios.push_back(g / e);
    }
  return ratios.empty() ? 1.0 : median(std::move(ratios));
}

// Per-frame scores averaged over all frames and over the rotation frames alone.
class ScoreMeans {
 public:
  void add(const MetricDepthScore& s, bool rotation) {
    all_.add(s);
    if (rotation) rotation_.add(s);
  }
  int frames() const { return all_.n; }
  int rotationFrames() const { return rotation_.n; }
  nlohmann::json json() const {
    return {{"abs_rel", all_.absRel()},
            {"delta1", all_.delta1()},
            {"abs_rel_rotation", rotation_.absRel()},
            {"delta1_rotation", rotation_.delta1()}};
  }

 private:
  struct Mean {
    double abs_rel_sum = 0, delta1_sum = 0;
    int n = 0;
    void add(const MetricDepthScore& s) { abs_rel_sum += s.abs_rel, delta1_sum += s.delta1, ++n; }
    nlohmann::json absRel() const { return n ? nlohmann::json(abs_rel_sum / n) : nlohmann::json(nullptr); }
    nlohmann::json delta1() const { return n ? nlohmann::json(delta1_sum / n) : nlohmann::json(nullptr); }
  };
  Mean all_, rotation_;
};

// Without --maps the configuration's map; without --model the configuration's model.
nlohmann::json runDepthBench(Config config, const std::optional<std::string>& maps_flag, int spawns,
                             const std::optional<std::string>& model_flag) {
  tools::requireEngineWorld(config, "valerant_bench depth");
  const std::vector<std::string> maps =
      maps_flag ? commaList("--maps", *maps_flag) : std::vector<std::string>{config.world.map};
  // --model is relative to the working directory, the configured model to the package folder.
  const std::string model =
      model_flag ? std::filesystem::absolute(*model_flag).string() : packageFilePath(config.slam.depth_prior_model);
  std::vector<ActionSequence> sequences;  // validated before any map is loaded
  for (const char* c : {"uw", "jw", "lw", "jq", "lq"}) sequences.push_back(makeActionSequence(c, config));
  cv::setNumThreads(1);
  const DepthPrior prior(model, cv::Size(config.slam.depth_prior_width, config.slam.depth_prior_height));
  const cv::Size net_size = prior.netSize(), output_size = prior.outputSize();

  ScoreMeans prior_scores, sweep_scores;
  std::vector<double> prior_ms, prior_cpu_ms;
  double coverage_sum = 0;
  long coverage_frames = 0, in_solid_frames = 0;
  std::vector<std::string> skipped_spawns;
  for (const std::string& name : maps) {
    config.world.map = name;
    const auto map = quake3::loadQuake3Map(name, config.world.patch_level);
    for (int spawn = 0; spawn < spawns; ++spawn) {
      config.world.spawn = spawn;
      std::optional<quake3::Quake3World> made;
      try {
        made.emplace(map, config);
      } catch (const InputError& e) {  // a spawn over the void or in solid: named in the output
        skipped_spawns.push_back(name + " " + std::to_string(spawn) + ": " + e.what());
        continue;
      }
      quake3::Quake3World& world = *made;
      auto slam = makeSlam("visual", world.intrinsics(), config, nullptr);  // visual: no ground truth read
      for (const cv::Mat& frame : world.context().frames) slam->track(SlamInput{frame, {}});
      const CheckpointId start = world.checkpoint();
      for (const ActionSequence& seq : sequences) {
        world.restore(start);
        const Rollout rollout = world.rollout(seq);
        const bool rotation = seq.rotationOnly();
        auto branch = slam->branch();
        for (size_t i = 0; i < rollout.frames.size(); ++i) {
          const TrackedFrame tracked = branch->track(SlamInput{rollout.frames[i], {}});
          if (i % kFrameStride != 0) continue;
          if (rollout.truth.at(i).in_solid) {
            ++in_solid_frames;
            continue;
          }
          cv::Mat truth;
          cv::resize(rollout.truth.at(i).depth_m, truth, output_size, 0, 0, cv::INTER_NEAREST);

          const ThreadClock t0 = ThreadClock::now();
          const DepthPrediction predicted = prior.predict(rollout.frames[i]);
          const ThreadClock spent = ThreadClock::now() - t0;
          prior_ms.push_back(1e3 * spent.wall);
          prior_cpu_ms.push_back(1e3 * spent.cpu);
          if (const auto s = scoreMetricDepth(predicted.depth_m, truth)) prior_scores.add(*s, rotation);

          // Coverage over every scored frame, those without any plane-sweep depth included.
          const cv::Mat& sweep = tracked.depth;
          const double covered = sweep.empty() ? 0 : cv::countNonZero(sweep > 0);  // NaN > 0 is false
          coverage_sum += sweep.empty() ? 0 : covered / static_cast<double>(sweep.total());
          ++coverage_frames;
          if (sweep.empty() || covered == 0) continue;
          cv::Mat sweep_small;
          cv::resize(sweep, sweep_small, output_size, 0, 0, cv::INTER_NEAREST);
          if (const auto s = scoreMetricDepth(sweep_small, truth, medianScale(sweep_small, truth))) sweep_scores.add(*s, rotation);
        }
      }
    }
  }

  nlohmann::json prior_json = prior_scores.json();
  prior_json["ms_per_frame"] = median(prior_ms);
  // The net runs on this thread alone: its CPU time is the cost on an idle core, which
  // the wall time is only when nothing else runs.
  prior_json["cpu_ms_per_frame"] = median(prior_cpu_ms);
  nlohmann::json sweep_json = sweep_scores.json();
  sweep_json["coverage"] = coverage_frames ? coverage_sum / coverage_frames : 0.0;
  sweep_json["frames"] = sweep_scores.frames();
  sweep_json["rotation_frames"] = sweep_scores.rotationFrames();
  return {{"bench", "depth"},
          {"maps", maps},
          {"spawns", spawns},
          {"in_solid_frames_skipped", in_solid_frames},
          {"spawns_skipped", skipped_spawns},
          {"frames", prior_scores.frames()},
          {"rotation_frames", prior_scores.rotationFrames()},
          {"net_width", net_size.width},
          {"net_height", net_size.height},
          {"output_width", output_size.width},
          {"output_height", output_size.height},
          {"prior", prior_json},
          {"plane_sweep", sweep_json},
          {"model", model}};
}

}  // namespace

BenchRun addBenchDepth(CLI::App& bench) {
  CLI::App* app = bench.add_subcommand("depth",
                                       "the learned depth prior's accuracy and time per frame against the "
                                       "engine's depth, next to the visual SLAM's plane-sweep depth");
  auto tool_config = std::make_shared<ToolConfig>(*app);
  auto maps = std::make_shared<std::string>();
  auto spawns = std::make_shared<int>(2);
  auto model = std::make_shared<std::string>();
  const CLI::Option* maps_flag =
      app->add_option("--maps", *maps, "maps, comma-separated (default: the configuration's world.map)")
          ->type_name("LIST");
  addInteger(*app, "--spawns", *spawns, "spawn points 0 to N-1 of every map", 1);
  const CLI::Option* model_flag =
      addPath(*app, "--model", *model,
              "ONNX depth model (default: the configuration's slam.depth_prior_model)", "FILE");
  return [=] {
    return runDepthBench(tool_config->document().parse(), maps_flag->count() ? std::optional(*maps) : std::nullopt,
                         *spawns, model_flag->count() ? std::optional(*model) : std::nullopt);
  };
}

}  // namespace valerant::tools
