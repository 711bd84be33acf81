#include "valerant/eval/episode_outputs.h"

#include <chrono>
#include <filesystem>
#include <future>
#include <opencv2/imgproc.hpp>

#include "valerant/common/error.h"
#include "valerant/common/output_file.h"
#include "valerant/common/tum_trajectory.h"
#include "valerant/eval/coverage_curve.h"
#include "valerant/eval/episode_truth.h"
#include "valerant/eval/map_accuracy.h"
#include "valerant/eval/spawn_departure.h"
#include "valerant/eval/trap_figures.h"
#include "valerant/eval/trajectory_metrics.h"
#include "valerant/explore/episode_json.h"
#include "valerant/explore/stage_seconds.h"
#include "valerant/explore/goal_map_image.h"
#include "valerant/explore/topdown_image.h"
#include "valerant/map/run_exports.h"
#include "valerant/map/eye_height_drift.h"
#include "valerant/map/run_map.h"
#include "valerant/world/quake3/reachable_floor.h"
#include "valerant/world/quake3/surface_samples.h"
#include "valerant/world/quake3/units.h"

namespace valerant {
namespace {

constexpr float kSurfaceSamplesPerSquareMetre = 50;  // 14 cm spacing: accuracy to ~7 cm
constexpr int kTopdownPixelsPerCell = 16;  // 16 px per metre-sized cell: a 40 m map is ~700 px

// The map of a finished episode; scaled by the eye height, or 1 for the oracle SLAM
// whose map is metric (map_frame.h).
RunMap runMapOf(const Episode& episode) {
  const bool metric_slam = episode.config().slam.backend == "oracle";  // the BSP frame in metres (oracle_slam.h)
  return RunMap{episode.config(), episode.map(),
                mapFrameOf(episode.gridAnchor(), episode.gridHeading(), metric_slam, episode.config()),
                episode.trajectory(), nlohmann::json::object()};
}

using Clock = std::chrono::steady_clock;

// `seconds`: the time of each part is added to it.
nlohmann::json groundTruth(const Episode& episode, const quake3::Quake3Map& map, const std::vector<FusedPoint>& cloud,
                           nlohmann::json& seconds) {
  const Config& config = episode.config();
  const auto spawn = map.bsp.spawnPoints().at(config.world.spawn);
  auto t = Clock::now();
  const auto reachable = quake3::floodFillReachableFloor(*map.collision, spawn.origin);
  seconds["reachable_floor"] = secondsSince(t);
  t = Clock::now();
  const EpisodeTruth truth = evaluateEpisodeTruth(episode, reachable);
  seconds["episode_truth"] = secondsSince(t);
  t = Clock::now();
  std::vector<Eigen::Vector3d> map_metres;
  if (truth.aligned || truth.floor_aligned)
    for (const auto& p : cloud) map_metres.push_back(truth.map_to_world_metres.apply(p.position.cast<double>()));
  const MapAccuracy accuracy =
      mapAccuracy(map_metres, quake3::sampleSurfaces(map.geometry, kSurfaceSamplesPerSquareMetre, config.world.seed),
                  episode.truth(),
                  CameraIntrinsics::fromHorizontalFov(config.world.width, config.world.height, config.world.fov_x_deg));
  seconds["map_accuracy"] = secondsSince(t);
  const CoverageCurve curve = coverageByCommittedStep(episode.history(), truth.observed_percent_by_step);
  int penetration_free_steps = 0;  // committed steps none of whose frames entered solid
  for (const auto& s : episode.history()) penetration_free_steps += s.chosen >= 0 && stepInSolidFrames(s) == 0;
  const ForcedTurns forced = forcedTurns(episode.history());
  const FinalStreakWays streak = finalStreakWays(episode.history(), config);
  nlohmann::json events = nlohmann::json::array();
  for (const PenetrationEvent& e : penetrationEvents(episode.history()))
    events.push_back({{"step", e.step},
                      {"candidate", e.candidate},
                      {"frames", e.frames},
                      {"frames_in_solid", e.frames_in_solid},
                      {"frames_outside_world", e.frames_outside_world},
                      {"frames_clip_only", e.frames_clip_only},
                      {"first_frame", e.first_frame},
                      {"occupied_max", e.occupied_max},
                      {"min_near_ratio", e.min_near_ratio}});
  return {{"committed_frames", truth.committed_frames},
          {"penetrations", truth.penetrating_frames},  // the union of the two below
          {"penetrations_in_solid", truth.penetrating_frames_in_solid},
          {"penetrations_outside_world", truth.penetrating_frames_outside_world},
          {"penetrations_clip_only", truth.penetrating_frames_clip_only},
          {"discarded_penetrations", truth.discarded_penetrating_frames},
          {"penetration_events", events},
          {"penetration_free_steps", penetration_free_steps},
          {"reachable_m2", truth.reachable_m2},
          {"observed_reachable_m2", truth.observed_reachable_m2},
          {"observed_reachable_percent", truth.observed_reachable_percent},
          {"in_view_reachable_m2", truth.in_view_reachable_m2},
          {"in_view_reachable_percent", truth.in_view_reachable_percent},
          {"aligned", truth.aligned},
          {"floor_aligned", truth.floor_aligned},
          {"ate_rmse_m", truth.alignment_rmse_m},
          {"ate_percent", truth.ate_percent},
          {"tilt_median_deg", truth.tilt_median_deg},
          {"tilt_p90_deg", truth.tilt_p90_deg},
          {"observed_percent_by_step", truth.observed_percent_by_step},
          {"coverage_curve",
           {{"committed_step", curve.committed_step},
            {"observed_percent", curve.observed_percent},
            {"wall_seconds", curve.wall_seconds}}},
          {"accuracy_median_m", accuracy.median_m},
          {"accuracy_p90_m", accuracy.p90_m},
          {"completeness_percent", accuracy.completeness_percent},
          {"verdicts", truth.verdicts},
          {"truly_colliding", truth.truly_colliding},
          {"predicted_colliding", truth.predicted_colliding},
          {"false_rejections", truth.false_rejections},
          {"missed_collisions", truth.missed_collisions},
          {"clean_blocked_by_failed_region", cleanTranslationsBlockedByFailedRegion(episode.history())},
          {"final_streak_translations", streak.translations},
          {"final_streak_clean_translations", streak.clean_translations},
          {"turn_steps", forced.turns},
          {"falsely_forced_turns", forced.falsely_forced}};
}

// Closures made (each with its numbers) and verified candidates rejected, counted by
// reason (loop_verifier.h), over the committed history; with ground truth, the ATE of
// the same path as the SLAM made it (no closures), beside the report's corrected one.
nlohmann::json loopClosures(const Episode& episode) {
  const LoopClosure* closure = episode.loopClosure();
  nlohmann::json out = {{"enabled", closure != nullptr}, {"made", 0}, {"rejected", 0},
                        {"rejected_by_reason", nlohmann::json::object()}, {"closures", nlohmann::json::array()}};
  if (!closure) return out;
  out["keyframes"] = closure->keyframes();
  out["scale_corrections"] = closure->scaleCorrections();  // loop_closure.eye_height_weight
  out["level_corrections"] = closure->levelCorrections();  // loop_closure.level_weight
  out["optimisations"] = closure->optimisations();
  out["unconverged_optimisations"] = closure->unconvergedOptimisations();  // stopped at max_iterations
  out["keyframes_rewritten"] = closure->keyframesRewritten();  // corrected copies made
  const size_t n = std::min(closure->odometry().size(), episode.truth().size());
  if (n > 0) {
    std::vector<Eigen::Isometry3d> truth_metres;
    for (size_t i = 0; i < n; ++i) {
      Eigen::Isometry3d pose = episode.truth()[i].camera_to_world;
      pose.translation() /= quake3::kUnitsPerMetre;
      truth_metres.push_back(pose);
    }
    const TrajectoryError slam = trajectoryError(
        std::vector<Eigen::Isometry3d>(closure->odometry().begin(), closure->odometry().begin() + n), truth_metres);
    if (slam.aligned) {
      out["slam_ate_rmse_m"] = slam.ate_rmse;
      out["slam_ate_percent"] = slam.ate_percent;
    }
  }
  for (const LoopClosureRecord& r : closure->records()) {
    const LoopVerification& v = r.verification;
    if (!v.accepted) {
      out["rejected"] = out["rejected"].get<int>() + 1;
      out["rejected_by_reason"][v.reason] = out["rejected_by_reason"].value(v.reason, 0) + 1;
      continue;
    }
    out["made"] = out["made"].get<int>() + 1;
    out["closures"].push_back({{"step", r.step},
                               {"new_keyframe", r.new_keyframe},
                               {"old_keyframe", r.old_keyframe},
                               {"matches", v.matches},
                               {"inliers", v.inliers},
                               {"offset_eye_heights", v.offset_eye_heights},
                               {"rotation_deg", v.rotation_deg},
                               {"scale_ratio", v.scale_ratio}});
  }
  return out;
}

}  // namespace

nlohmann::json runReportHeader(const std::string& tool, const Config& config) {
  return {{"tool", tool},
          {"world", config.world.backend},
          {"map", config.world.map},
          {"spawn", config.world.spawn},
          {"slam", config.slam.backend},
          {"policy", config.policy.kind},
          {"seed", config.world.seed},
          {"budget", config.policy.budget_steps},
          {"rf", config.floor.enabled},
          {"col_pc", config.collision.pointcloud_enabled},
          {"col_depth", config.collision.depth_enabled},
          {"dp", config.dead_pocket.enabled},
          {"loop_closure", config.loop_closure.enabled}};
}

double snapshotAfterStep(RunSnapshot& snapshot, const Episode& episode, const StepRecord& step,
                         const nlohmann::json& header, SnapshotSchedule& schedule) {
  if (step.chosen < 0 && !step.rewind) return 0;  // a stall leaves the map as it was
  auto seconds = [](Clock::time_point t) { return std::chrono::duration<double>(t.time_since_epoch()).count(); };
  const double start = seconds(Clock::now());
  if (!schedule.due(start)) return 0;
  nlohmann::json report = header;
  report["steps"] = step.step;
  report["committed_steps"] = episode.committedSteps();
  snapshot.write(runMapOf(episode), report);
  const double end = seconds(Clock::now());
  schedule.written(start, end);
  return end - start;
}

void writeEpisodeOutputs(const Episode& episode, const quake3::Quake3Map* map, const std::string& out, bool overwrite,
                         nlohmann::json& report) {
  const Config& config = episode.config();
  const std::vector<FusedPoint> cloud =
      episode.map().voxelCloud(config.map.voxel_eye_heights * episode.anchorEyeHeight());
  nlohmann::json seconds = nlohmann::json::object();  // of each part below
  // The map kept for valerant_export, and every export format through the same code.
  auto t = Clock::now();
  const RunMap run = runMapOf(episode);
  report["run_map"] = saveRunMap(out, run, overwrite);
  seconds["run_map"] = secondsSince(t);
  // The exports (the mesh most) read only `run`, the rest below only the episode: they
  // run beside each other, on the machine's two cores. get() rethrows an export's error;
  // an error here first waits for the exports (the future's destructor).
  std::future<std::pair<nlohmann::json, double>> exports = std::async(std::launch::async, [&] {
    const auto start = Clock::now();
    nlohmann::json written = exportRunMap(run, exportFormats(), out, overwrite);
    return std::pair{std::move(written), secondsSince(start)};
  });
  t = Clock::now();
  writeTumTrajectory(out + "/" + run_files::kTrajectory, episode.trajectory());
  // A world without ground truth (the learned world from a screenshot) has no true path.
  const bool has_truth = !episode.truth().empty();
  if (has_truth) {
    std::vector<Eigen::Isometry3d> truth_poses;
    for (const FrameTruth& t : episode.truth()) truth_poses.push_back(t.camera_to_world);
    writeTumTrajectory(out + "/gt_trajectory.txt", truth_poses);
  }
  cv::Mat topdown = drawTopdown(cloud, episode.grid(), episode.trajectory(), episode.history(), episode.failed(),
                                config.collision, kTopdownPixelsPerCell);
  cv::cvtColor(topdown, topdown, cv::COLOR_RGB2BGR);
  writeImageAtomically(out + "/topdown.png", topdown);
  // Where the whole-level goal can lead from where the agent stopped (goal_map_image.h).
  Cell agent{-1, -1};
  if (!episode.trajectory().empty()) episode.grid().cellOf(episode.trajectory().back().translation(), agent);
  cv::Mat goal_map =
      drawGoalMap(episode.grid(), episode.goalFrom(agent), episode.failed(), agent, kTopdownPixelsPerCell);
  cv::cvtColor(goal_map, goal_map, cv::COLOR_RGB2BGR);
  writeImageAtomically(out + "/goal_map.png", goal_map);
  // The player's view at the end, for viewers of the run (run_publisher's camera image).
  cv::Mat view = episode.currentView();
  if (!view.empty()) {
    cv::cvtColor(view, view, cv::COLOR_RGB2BGR);
    writeImageAtomically(out + "/view.png", view);
  }

  StageSeconds total;
  double wall = 0;
  for (const auto& s : episode.history()) {
    total += s.seconds;
    wall += s.wall_seconds;
  }
  report["committed_steps"] = episode.committedSteps();
  report["steps"] = episode.history().size();
  report["rewinds"] = episode.rewinds();
  report["first_translation_step"] = firstTranslationStep(episode.history());  // 0: none (spawn_departure.h)
  report["final_turn_streak"] = finalTurnStreak(episode.history());  // steps turning in place at the end (trap_figures.h)
  report["final_streak_reversals"] = finalStreakWays(episode.history(), config).reversals;
  const GoalReach reach = goalReach(episode.history());
  report["goal_unreachable_steps"] = reach.unreachable_steps;
  report["goal_cut_off_by_failed_steps"] = reach.cut_off_by_failed_steps;
  report["stuck"] = episode.stuck();  // ended early: a stall with no rewind left (episode.h)
  report["failed_cells"] = episode.failed().cells().size();
  report["map_points"] = cloud.size();
  // The map's scale where each keyframe was made, by the eye height (eye_height_drift.h).
  const EyeHeightDrift drift = eyeHeightDrift(episode.map().keyframes(), episode.anchorEyeHeight());
  report["eye_height_drift"] = {{"measured_keyframes", drift.measured_keyframes},
                                {"min_ratio", drift.min_ratio},
                                {"max_ratio", drift.max_ratio},
                                {"last_ratio", drift.last_ratio}};
  report["stage_seconds"] = toJson(total);
  report["wall_seconds"] = wall;
  // Counted from the frames' truth: null (not recorded) without it.
  report["frames_rendered"] = nullptr;
  if (has_truth) {
    size_t n = 0;
    for (const auto& s : episode.history())
      for (const auto& c : s.candidates) n += c.truth.size();
    report["frames_rendered"] = n;
  }
  report["loop_closures"] = loopClosures(episode);
  seconds["trajectories_and_images"] = secondsSince(t);
  t = Clock::now();
  // null: no ground truth (no engine map: the learned world from a screenshot, a bag).
  nlohmann::json truth_seconds = nlohmann::json::object();
  report["ground_truth"] = map ? groundTruth(episode, *map, cloud, truth_seconds) : nlohmann::json();
  seconds["ground_truth"] = secondsSince(t);
  seconds["ground_truth_parts"] = truth_seconds;
  t = Clock::now();
  auto [written, export_seconds] = exports.get();
  seconds["waiting_for_exports"] = secondsSince(t);
  seconds["exports"] = export_seconds;
  report["exports"] = std::move(written);
  nlohmann::json files = report["exports"]["files"];
  files.insert(files.end(), {run_files::kKeyframePoints, run_files::kKeyframePoses, run_files::kConfig,
                             run_files::kTrajectory});
  if (has_truth) files.push_back("gt_trajectory.txt");
  files.insert(files.end(), {"topdown.png", "goal_map.png", "decisions.jsonl", run_files::kReport});
  if (!view.empty()) files.push_back("view.png");
  report["files"] = files;
  report["output_stage_seconds"] = seconds;
}

void writeRunReport(const std::string& out, const nlohmann::json& report) {
  writeFileAtomically(out + "/report.json", report.dump(2) + '\n');
  std::error_code error;  // the snapshot is a convenience copy now: failing to remove it loses nothing
  std::filesystem::remove_all(runSnapshotDir(out), error);
}

}  // namespace valerant
