// valerant_slam: runs a SLAM backend on engine rollouts and scores it against the
// engine's ground truth. The SLAM tracks the committed context (the spawn view), then
// one branch per candidate tracks that candidate's rollout, as the explorer does.
// Per candidate it writes the estimated TUM trajectory (SLAM units) next to the
// ground-truth one (metres), the keyframe clouds as PLY (x y z rgb confidence) and every
// frame's depth and confidence (32-bit float TIFF, SLAM units); stdout gets one JSON
// line, logs go to stderr. OpenCV runs single-threaded so that frames per second are
// per branch on one core (pin the process with taskset for a clean figure).
//
//   valerant_slam --map oa_dm1 [--spawn 0] [--candidates uw,jw,lw,jq,lq]
//                 [--slam visual|oracle] [--config FILE] [--set key=value ...] --out DIR
//                 (--help: every flag)
#include <filesystem>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "thread_clock.h"
#include "tool_config.h"
#include "valerant/common/output_file.h"
#include "valerant/common/tum_trajectory.h"
#include "valerant/eval/trajectory_metrics.h"
#include "valerant/map/map_exports.h"
#include "valerant/slam/rollout_truth.h"
#include "valerant/slam/slam_factory.h"
#include "valerant/world/quake3/quake3_world.h"
#include "valerant/world/quake3/units.h"

using namespace valerant;
namespace fs = std::filesystem;

namespace {

using Clock = tools::ThreadClock;

nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

void writeImage(const std::string& path, const cv::Mat& image) {
  writeImageAtomically(path, image);
}

void writeCloud(const std::string& path, const std::vector<KeyframeCloud>& clouds) {
  std::vector<FusedPoint> points;
  for (const auto& kf : clouds)
    for (const auto& p : kf.points) points.push_back({p.position, p.rgb, p.confidence, 0.f});
  if (points.empty()) {
    std::cerr << "valerant_slam: no keyframe points, " << path << " not written\n";
    return;
  }
  writeCloudPly(path, points, true);
}

struct Track {
  std::vector<TrackedFrame> frames;
  Clock time;
};

// `truth` holds the rollout's ground truth while it is tracked (the oracle reads it).
Track trackFrames(Slam& slam, const Rollout& r, RolloutTruth& truth) {
  Track t;
  const RolloutTruth::Hold held = truth.hold(r);
  for (size_t i = 0; i < r.frames.size(); ++i) {
    const SlamInput in{r.frames[i], {r.id, static_cast<int>(i)}};
    const Clock start = Clock::now();
    t.frames.push_back(slam.track(in));
    t.time += Clock::now() - start;
  }
  return t;
}

// Mean wall milliseconds of one snapshot() + restore() of `slam`'s current state.
double snapshotRestoreMs(Slam& slam) {
  constexpr int kRepeats = 50;
  const Clock start = Clock::now();
  for (int i = 0; i < kRepeats; ++i) slam.restore(slam.snapshot());
  return 1e3 * (Clock::now() - start).wall / kRepeats;
}

nlohmann::json evaluateCandidate(const std::string& name, const Rollout& context, const Rollout& rollout,
                                 Slam& branch, const Track& track, double min_confidence, const std::string& dir) {
  fs::create_directories(dir + "/depth");
  fs::create_directories(dir + "/confidence");
  std::vector<Eigen::Isometry3d> truth;
  for (const Rollout* r : {&context, &rollout})
    for (const FrameTruth& t : r->truth) {
      Eigen::Isometry3d metres = t.camera_to_world;
      metres.translation() /= quake3::kUnitsPerMetre;
      truth.push_back(metres);
    }
  const std::vector<Eigen::Isometry3d> estimate = branch.trajectory();
  writeTumTrajectory(dir + "/trajectory.txt", estimate);
  writeTumTrajectory(dir + "/gt_trajectory.txt", truth);
  writeCloud(dir + "/keyframes.ply", branch.keyframeClouds());

  std::vector<cv::Mat> depth, confidence, truth_depth;
  int in_solid = 0, rotation_only = 0;
  std::vector<size_t> lost;  // frame indices
  for (size_t i = 0; i < track.frames.size(); ++i) {
    const TrackedFrame& f = track.frames[i];
    char file[32];
    std::snprintf(file, sizeof(file), "%06zu.tiff", i);
    writeImage(dir + "/depth/" + file, f.depth);
    writeImage(dir + "/confidence/" + file, f.confidence);
    depth.push_back(f.depth);
    confidence.push_back(f.confidence);
    truth_depth.push_back(rollout.truth[i].depth_m);
    if (f.state == TrackingState::kLost) lost.push_back(i);
    rotation_only += f.rotation_only;
    in_solid += rollout.truth[i].in_solid;
  }
  nlohmann::json out = {{"candidate", name}, {"frames", track.frames.size()}, {"dir", dir}};
  if (estimate.size() == truth.size()) {
    const TrajectoryError e = trajectoryError(estimate, truth);
    out["path_m"] = e.path_length;
    out["ate_m"] = e.ate_rmse;
    out["ate_percent"] = number(e.ate_percent);
    out["rotation_rmse_deg"] = e.rotation_rmse_deg;
    out["sim3_scale"] = e.aligned ? number(e.alignment.scale) : nullptr;
  }
  const DepthError d = depthError(depth, confidence, truth_depth, min_confidence);
  out["depth_abs_rel"] = number(d.abs_rel);
  out["depth_scale"] = number(d.scale);
  out["confident_fraction"] = d.confident_fraction;
  out["fps"] = track.frames.size() / track.time.wall;
  out["fps_cpu"] = track.frames.size() / track.time.cpu;
  out["lost_frames"] = lost.size();
  out["lost_frame_indices"] = lost;
  out["in_solid_frames"] = in_solid;
  out["rotation_only_frames"] = rotation_only;
  out["keyframes"] = branch.keyframeCount();
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Runs a SLAM backend on engine rollouts (the spawn view, then one branch per candidate) and "
      "scores it against the engine's ground truth.",
      "valerant_slam"};
  tools::useToolConventions(app);
  tools::ToolConfig tool_config(app);
  tool_config.keyFlag("--map", "world.map", "MAP", "map name or PK3:MAP");
  tool_config.keyFlag("--spawn", "world.spawn", "INT", "spawn point index");
  tool_config.keyFlag("--slam", "slam.backend", "visual|oracle", "SLAM backend");
  std::string out, candidates = "uw,jw,lw,jq,lq";
  tools::addPath(app, "--out", out, "output folder", "DIR")->required();
  app.add_option("--candidates", candidates, "candidates or key strings, comma-separated")
      ->type_name("LIST")
      ->capture_default_str();
  return tools::runTool(app, argc, argv, [&] {
    const Config config = tool_config.document().parse();
    tools::requireEngineWorld(config, "valerant_slam");
    const std::string backend = config.slam.backend;
    std::vector<ActionSequence> sequences;  // validated before any rendering
    tools::checkFlagValues([&] {
      for (const auto& c : tools::commaList("--candidates", candidates))
        sequences.push_back(makeActionSequence(c, config));
    });
    cv::setNumThreads(1);

    auto map = quake3::loadQuake3Map(config.world.map, config.world.patch_level);
    quake3::Quake3World world(map, config);
    const auto truth = std::make_shared<RolloutTruth>();
    auto slam = makeSlam(backend, world.intrinsics(), config, truth);
    std::cerr << "valerant_slam: " << backend << " SLAM on " << config.world.map << " spawn " << config.world.spawn
              << ", " << sequences.size() << " candidates\n";
    fs::create_directories(out);
    const Rollout context = world.context();
    trackFrames(*slam, context, *truth);

    nlohmann::json candidates = nlohmann::json::array();
    const CheckpointId start = world.checkpoint();
    for (const auto& seq : sequences) {
      world.restore(start);
      const Rollout rollout = world.rollout(seq);
      auto branch = slam->branch();
      const Track track = trackFrames(*branch, rollout, *truth);
      const std::string dir = out + "/" + (seq.name.find(':') == std::string::npos ? seq.name : "custom");
      nlohmann::json c = evaluateCandidate(seq.name, context, rollout, *branch, track,
                                           config.collision.min_confidence, dir);
      c["snapshot_restore_ms"] = snapshotRestoreMs(*branch);
      std::cerr << "valerant_slam: " << c.dump() << "\n";
      candidates.push_back(c);
    }
    const nlohmann::json line = {{"tool", "valerant_slam"}, {"map", config.world.map},
                                 {"spawn", config.world.spawn}, {"slam", backend},
                                 {"out", out},          {"candidates", candidates}};
    std::cout << line.dump() << std::endl;
    return 0;
  });
}
