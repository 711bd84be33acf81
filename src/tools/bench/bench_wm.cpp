// valerant_bench wm: the learned world model (world/learned/world_model_net.h) against
// the engine, from the same state for the same keys. For each map and each of its first
// N spawns the engine renders the spawn frame and the five paper candidates' frames at
// the model's frame size (the size its training data was rendered at); the model starts
// from the spawn frame repeated K times (a single screenshot) and imagines each
// candidate frame by frame, feeding its own frames back. Scored:
//   horizons  PSNR and SSIM (eval/image_similarity.h) of the frame after 8, 16, 32, 57
//             and 97 actions against the engine's, next to two baselines: `repeat` (the
//             last context frame) and `flat` (every pixel the true frame's mean colour);
//             each horizon counts the rollouts that reach it (97: jw, lw only) with the
//             engine's camera outside solid there (inside a wall the engine shows the
//             wall's inside, a near-uniform image that no model can be asked for and
//             that `flat` matches exactly; such frames are counted apart).
//   motion    our visual SLAM as the explorer runs it (the context, then a branch per
//             candidate; frames resized to the configured camera, world.width x height
//             and fov_x_deg, as the learned backend shows them, the size the SLAM's pixel
//             parameters were tuned at) on the generated frames
//             and on the engine's, the recovered path carried into the world by the
//             known first pose; yaw and heading errors at the rollout's end
//             (eval/end_of_path_error.h) and the frames it lost, those where the
//             engine's camera is in solid also counted apart.
//   depth     the depth prior on every 4th generated frame and on the engine's frame at
//             the same pose, both against the engine's depth on the same pixels (the
//             prior gives a depth everywhere), frames in solid left out
//             (eval/metric_depth_score.h, valerant_bench depth's protocol).
//   time      CPU milliseconds of one model step on this thread (OpenCV single-threaded).
// With --out, one comparison sheet per map and spawn: a row per candidate, a column per
// horizon, the engine's frame above the model's.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "../thread_clock.h"
#include "../tool_config.h"
#include "bench.h"
#include "valerant/common/comparison_sheet.h"
#include "valerant/common/output_file.h"
#include "valerant/config/package_dir.h"
#include "valerant/dataset/map_sets.h"
#include "valerant/eval/end_of_path_error.h"
#include "valerant/eval/image_similarity.h"
#include "valerant/eval/metric_depth_score.h"
#include "valerant/common/depth_prior.h"
#include "valerant/slam/slam_factory.h"
#include "valerant/world/learned/learned_world.h"
#include "valerant/world/learned/world_model_net.h"
#include "valerant/world/quake3/quake3_world.h"

namespace valerant::tools {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const std::vector<int> kHorizons = {8, 16, 32, 57, 97};  // frames after that many actions
constexpr size_t kDepthFrameStride = 4;                  // as valerant_bench depth

json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  auto middle = v.begin() + static_cast<long>(v.size() / 2);
  std::nth_element(v.begin(), middle, v.end());
  return *middle;
}

// Mean PSNR and SSIM of one kind of prediction at one horizon.
class SimilarityMean {
 public:
  void add(const cv::Mat& predicted, const cv::Mat& truth) {
    psnr_ += psnrDb(predicted, truth), ssim_ += ssim(predicted, truth), ++n_;
  }
  json toJson() const {
    return {{"psnr", n_ ? number(psnr_ / n_) : json(nullptr)}, {"ssim", n_ ? number(ssim_ / n_) : json(nullptr)}};
  }
  int count() const { return n_; }

 private:
  double psnr_ = 0, ssim_ = 0;
  int n_ = 0;
};

struct HorizonScores {
  SimilarityMean model, repeat, flat;
  int in_solid = 0;  // rollouts whose frame there is in solid: not scored
};

// Every pixel the mean colour of `truth`: the best constant image in the MSE sense.
cv::Mat flatImage(const cv::Mat& truth) { return cv::Mat(truth.size(), truth.type(), cv::mean(truth)); }

// End-of-rollout errors and lost frames of the SLAM over many rollouts of one source.
class MotionScores {
 public:
  void add(const EndOfPathError& e, long lost_frames, long lost_in_solid) {
    yaw_.push_back(e.yaw_error_deg);
    if (e.heading_error_deg) heading_.push_back(*e.heading_error_deg);
    lost_frames_ += lost_frames;
    lost_in_solid_ += lost_in_solid;
    rollouts_with_lost_frames_ += lost_frames > 0;
  }
  json toJson() const {
    return {{"rollouts", yaw_.size()},
            {"yaw_error_deg", summary(yaw_)},
            {"heading_error_deg", summary(heading_)},
            {"lost_frames", lost_frames_},
            {"lost_frames_in_solid", lost_in_solid_},
            {"rollouts_with_lost_frames", rollouts_with_lost_frames_}};
  }

 private:
  static json summary(const std::vector<double>& v) {
    if (v.empty()) return {{"rollouts", 0}, {"mean", nullptr}, {"max", nullptr}};
    double sum = 0;
    for (double x : v) sum += x;
    return {{"rollouts", v.size()}, {"mean", sum / v.size()}, {"max", *std::max_element(v.begin(), v.end())}};
  }
  std::vector<double> yaw_, heading_;
  long lost_frames_ = 0, lost_in_solid_ = 0;
  int rollouts_with_lost_frames_ = 0;
};

// Per-frame depth AbsRel means on generated and engine frames.
struct DepthMeans {
  double generated_sum = 0, engine_sum = 0;
  int frames = 0;
  long in_solid_frames = 0;
};

// `model`'s frames for `actions` from `screenshot` repeated as the whole context, each
// step's CPU milliseconds appended to `step_ms`.
std::vector<cv::Mat> imagine(WorldModelNet& model, const cv::Mat& screenshot, const ActionSequence& actions,
                             std::vector<double>& step_ms) {
  std::vector<cv::Mat> context(model.contextFrames(), screenshot), frames;
  AnchorState anchor = model.startAnchor(screenshot);
  for (const MotionStep& step : actions.steps) {
    const ThreadClock start = ThreadClock::now();
    cv::Mat next = model.next(context, step, anchor);
    step_ms.push_back(1e3 * (ThreadClock::now() - start).cpu);
    context.erase(context.begin());
    context.push_back(next);
    frames.push_back(std::move(next));
  }
  return frames;
}

cv::Mat atSize(const cv::Mat& rgb, cv::Size size) {
  if (rgb.size() == size) return rgb;
  cv::Mat resized;
  cv::resize(rgb, resized, size, 0, 0, cv::INTER_LINEAR);
  return resized;
}

struct SlamRun {
  EndOfPathError error;
  long lost_frames = 0;
  long lost_in_solid = 0;  // of them, frames where the engine's camera is in solid
};

// A branch of `committed` (which has tracked the context) tracks `frames` of the
// rollout `engine` made; its path, context included, is scored against `path` (the
// context's and the rollout's true poses).
SlamRun trackRollout(const Slam& committed, const std::vector<cv::Mat>& frames, const Rollout& engine,
                     const std::vector<Eigen::Isometry3d>& path, bool translates) {
  const std::unique_ptr<Slam> branch = committed.branch();
  const cv::Size size(committed.intrinsics().width, committed.intrinsics().height);
  SlamRun run;
  for (size_t i = 0; i < frames.size(); ++i) {
    if (branch->track(SlamInput{atSize(frames[i], size), {}}).state != TrackingState::kLost) continue;
    ++run.lost_frames;
    run.lost_in_solid += engine.truth[i].in_solid;
  }
  run.error = endOfPathError(branch->trajectory(), path, translates);
  return run;
}

json slamJson(const SlamRun& run) {
  return {{"yaw_error_deg", run.error.yaw_error_deg},
          {"heading_error_deg", run.error.heading_error_deg ? json(*run.error.heading_error_deg) : json(nullptr)},
          {"lost_frames", run.lost_frames},
          {"lost_frames_in_solid", run.lost_in_solid}};
}

// A file name part for a map given as a name or as /path/file.pk3:map.
std::string fileStem(const std::string& map) {
  std::string stem = map.substr(map.find_last_of(":/") == std::string::npos ? 0 : map.find_last_of(":/") + 1);
  for (char& c : stem)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') c = '_';
  return stem;
}

void writeRgbPng(const std::string& path, const cv::Mat& rgb) {
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  writeImageAtomically(path, bgr);
}

struct Flags {
  std::optional<std::string> maps, model, out;
  int spawns = 1;
};

json runWorldModelBench(const Config& config, const Flags& flags) {
  const std::vector<std::string> maps =
      flags.maps ? commaList("--maps", *flags.maps) : dataset::loadMapSets(dataset::defaultMapSetsPath()).evaluation;
  // --model is relative to the working directory, the configured model to the package folder.
  const LearnedWorldConfig& learned = config.world.learned;
  const std::string model_path =
      flags.model ? fs::absolute(*flags.model).string() : packageFilePath(learned.model);
  std::vector<ActionSequence> sequences;  // validated before any map is loaded
  for (const std::string& c : candidateNames()) sequences.push_back(makeActionSequence(c, config));
  cv::setNumThreads(1);
  // As the backend loads it (with the depth prior a pose_anchor model starts from).
  Config model_config = config;
  model_config.world.learned.model = model_path;
  WorldModelNet model = loadWorldModelNet(model_config);
  const DepthPrior prior(packageFilePath(config.slam.depth_prior_model),
                         cv::Size(config.slam.depth_prior_width, config.slam.depth_prior_height));
  // The engine renders what the model was trained on; the SLAM sees the configured
  // camera, as behind the learned backend (learned_world.h: frames resized to it).
  Config engine_config = config;
  engine_config.world.width = model.width();
  engine_config.world.height = model.height();
  const CameraIntrinsics slam_camera =
      CameraIntrinsics::fromHorizontalFov(config.world.width, config.world.height, config.world.fov_x_deg);
  const cv::Size slam_size(slam_camera.width, slam_camera.height);
  if (flags.out) fs::create_directories(*flags.out);

  std::map<int, HorizonScores> horizons;
  MotionScores generated_motion, engine_motion;
  DepthMeans depth;
  std::vector<double> step_ms;
  json rollouts = json::array(), sheets = json::array();
  std::vector<std::string> skipped_spawns;
  for (const std::string& name : maps) {
    engine_config.world.map = name;
    const auto map = quake3::loadQuake3Map(name, engine_config.world.patch_level);
    for (int spawn = 0; spawn < flags.spawns; ++spawn) {
      engine_config.world.spawn = spawn;
      std::optional<quake3::Quake3World> made;
      try {
        made.emplace(map, engine_config);
      } catch (const InputError& e) {  // a spawn out of range: named in the output
        skipped_spawns.push_back(name + " " + std::to_string(spawn) + ": " + e.what());
        continue;
      }
      quake3::Quake3World& world = *made;
      const Rollout context = world.context();
      const cv::Mat screenshot = context.frames.back();
      const auto slam = makeSlam("visual", slam_camera, config, nullptr);
      for (const cv::Mat& frame : context.frames) slam->track(SlamInput{atSize(frame, slam_size), {}});
      std::vector<ComparisonRow> sheet_rows;
      const CheckpointId start = world.checkpoint();
      for (const ActionSequence& seq : sequences) {
        world.restore(start);
        const Rollout truth = world.rollout(seq);
        const std::vector<cv::Mat> generated = imagine(model, screenshot, seq, step_ms);
        std::cerr << "valerant_bench wm: " << name << " spawn " << spawn << " " << seq.name << ": "
                  << generated.size() << " frames imagined\n";

        ComparisonRow& row = sheet_rows.emplace_back(ComparisonRow{seq.name, {}, {}});
        for (int h : kHorizons) {
          const bool reached = h <= static_cast<int>(truth.frames.size());
          row.truth.push_back(reached ? truth.frames[h - 1] : cv::Mat());
          row.generated.push_back(reached ? generated[h - 1] : cv::Mat());
          if (!reached) continue;
          if (truth.truth[h - 1].in_solid) {
            ++horizons[h].in_solid;
            continue;
          }
          const cv::Mat& real = truth.frames[h - 1];
          horizons[h].model.add(generated[h - 1], real);
          horizons[h].repeat.add(screenshot, real);
          horizons[h].flat.add(flatImage(real), real);
        }

        std::vector<Eigen::Isometry3d> path;
        for (const Rollout* r : {&context, &truth})
          for (const FrameTruth& t : r->truth) path.push_back(t.camera_to_world);
        const bool translates = !seq.rotationOnly();
        const SlamRun on_generated = trackRollout(*slam, generated, truth, path, translates);
        const SlamRun on_engine = trackRollout(*slam, truth.frames, truth, path, translates);
        generated_motion.add(on_generated.error, on_generated.lost_frames, on_generated.lost_in_solid);
        engine_motion.add(on_engine.error, on_engine.lost_frames, on_engine.lost_in_solid);

        for (size_t i = 0; i < truth.frames.size(); i += kDepthFrameStride) {
          if (truth.truth[i].in_solid) {
            ++depth.in_solid_frames;
            continue;
          }
          cv::Mat true_depth;
          cv::resize(truth.truth[i].depth_m, true_depth, prior.outputSize(), 0, 0, cv::INTER_NEAREST);
          const auto on_model = scoreMetricDepth(prior.predict(generated[i]).depth_m, true_depth);
          const auto on_real = scoreMetricDepth(prior.predict(truth.frames[i]).depth_m, true_depth);
          if (!on_model || !on_real) continue;  // no true depth in range (all sky): not scored on either
          depth.generated_sum += on_model->abs_rel, depth.engine_sum += on_real->abs_rel, ++depth.frames;
        }
        rollouts.push_back({{"map", name},
                            {"spawn", spawn},
                            {"candidate", seq.name},
                            {"frames", truth.frames.size()},
                            {"in_solid_frames", std::count_if(truth.truth.begin(), truth.truth.end(),
                                                              [](const FrameTruth& t) { return t.in_solid; })},
                            {"slam_generated", slamJson(on_generated)},
                            {"slam_engine", slamJson(on_engine)}});
      }
      if (flags.out) {
        const std::string sheet = *flags.out + "/wm_" + fileStem(name) + "_spawn" + std::to_string(spawn) + ".png";
        std::vector<std::string> columns;
        for (int h : kHorizons) columns.push_back("frame " + std::to_string(h));
        writeRgbPng(sheet, makeComparisonSheet(sheet_rows, columns));
        sheets.push_back(sheet);
      }
    }
  }

  json horizon_json = json::array();  // in frame order
  for (const auto& [h, s] : horizons)
    horizon_json.push_back({{"frame", h},
                            {"rollouts", s.model.count()},
                            {"in_solid_skipped", s.in_solid},
                            {"model", s.model.toJson()},
                            {"repeat", s.repeat.toJson()},
                            {"flat", s.flat.toJson()}});
  return {{"bench", "wm"},
          {"maps", maps},
          {"spawns", flags.spawns},
          {"spawns_skipped", skipped_spawns},
          {"model", flags.model ? *flags.model : learned.model},  // as given: a record valid on any machine
          {"width", model.width()},
          {"height", model.height()},
          {"context_frames", model.contextFrames()},
          {"ssim", "mean of the R, G, B planes' SSIM: 11x11 Gaussian window, sigma 1.5, windows inside the image"},
          {"horizons", horizon_json},
          {"motion",
           {{"slam_width", slam_size.width},
            {"slam_height", slam_size.height},
            {"generated", generated_motion.toJson()},
            {"engine", engine_motion.toJson()}}},
          {"depth_abs_rel",
           {{"generated", depth.frames ? json(depth.generated_sum / depth.frames) : json(nullptr)},
            {"engine", depth.frames ? json(depth.engine_sum / depth.frames) : json(nullptr)},
            {"frames", depth.frames},
            {"in_solid_frames_skipped", depth.in_solid_frames},
            {"depth_model", config.slam.depth_prior_model}}},
          {"ms_per_frame", number(median(step_ms))},
          {"rollouts", rollouts},
          {"sheets", sheets},
          {"peak_rss_mib", peakResidentMiB()}};
}

}  // namespace

BenchRun addBenchWorldModel(CLI::App& bench) {
  CLI::App* app = bench.add_subcommand("wm",
                                       "the learned world model's rollouts against the engine's: PSNR/SSIM "
                                       "at five horizons, the SLAM's path on them, depth, time per frame");
  auto tool_config = std::make_shared<ToolConfig>(*app);
  auto maps = std::make_shared<std::string>(), model = std::make_shared<std::string>(),
       out = std::make_shared<std::string>();
  auto spawns = std::make_shared<int>(1);
  const CLI::Option* maps_flag =
      app->add_option("--maps", *maps, "maps, comma-separated (default: the evaluation maps of config/map_sets.yaml)")
          ->type_name("LIST");
  addInteger(*app, "--spawns", *spawns, "spawn points 0 to N-1 of every map", 1);
  const CLI::Option* model_flag = addPath(
      *app, "--model", *model, "ONNX world model (default: the configuration's world.learned.model)", "FILE");
  const CLI::Option* out_flag =
      addPath(*app, "--out", *out, "folder for one comparison sheet PNG per map and spawn", "DIR");
  return [=] {
    Flags flags;
    if (maps_flag->count()) flags.maps = *maps;
    if (model_flag->count()) flags.model = *model;
    if (out_flag->count()) flags.out = *out;
    flags.spawns = *spawns;
    return runWorldModelBench(tool_config->document().parse(), flags);
  };
}

}  // namespace valerant::tools
