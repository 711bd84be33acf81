#include "valerant/eval/episode_truth.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "valerant/common/median.h"
#include "valerant/eval/trajectory_metrics.h"
#include "valerant/world/quake3/units.h"

namespace valerant {
namespace {

constexpr double kStepHeightUnits = 18.0;  // Quake III STEPSIZE

using Cell2 = ReachableCells::Cell2;

Cell2 metreCell(double x_units, double y_units) {
  return {static_cast<int>(std::floor(x_units / quake3::kUnitsPerMetre)),
          static_cast<int>(std::floor(y_units / quake3::kUnitsPerMetre))};
}

}  // namespace

PenetrationCounts countPenetrations(const std::vector<FrameTruth>& truth) {
  PenetrationCounts c;
  for (const auto& f : truth) {
    c.frames += f.in_solid;
    c.in_solid += f.hull_in_solid;
    c.outside_world += f.outside_world;
    c.clip_only += f.hull_in_clip_only && !f.outside_world;
  }
  return c;
}

bool staysOutOfSolid(const CandidateRecord& candidate) {
  return !candidate.truth.empty() &&
         std::none_of(candidate.truth.begin(), candidate.truth.end(), [](const FrameTruth& f) { return f.in_solid; });
}

int stepInSolidFrames(const StepRecord& step) {
  int frames = 0;
  if (step.chosen >= 0)
    for (const auto& f : step.candidates.at(step.chosen).truth) frames += f.in_solid;
  return frames;
}

std::vector<PenetrationEvent> penetrationEvents(const std::vector<StepRecord>& history) {
  std::vector<PenetrationEvent> events;
  for (const auto& step : history) {
    const int frames = stepInSolidFrames(step);
    if (frames == 0) continue;
    const CandidateRecord& c = step.candidates.at(step.chosen);
    int first = 0;
    while (!c.truth[first].in_solid) ++first;
    const PenetrationCounts counts = countPenetrations(c.truth);
    events.push_back({step.step, c.verdict.candidate, frames, counts.in_solid, counts.outside_world,
                      counts.clip_only, first, c.verdict.occupied_max, c.verdict.min_near_ratio});
  }
  return events;
}

int committedInSolidFrames(const std::vector<StepRecord>& history) {
  int frames = 0;
  for (const auto& step : history) frames += stepInSolidFrames(step);
  return frames;
}

ReachableCells::ReachableCells(const quake3::ReachableFloor& reachable) {
  std::set<CellStorey> cells;
  for (const auto& c : reachable.cells) {
    const Cell2 key = metreCell(c.x(), c.y());
    heights_[key].push_back(c.z());
    cells.insert({key, storeyOf(c.z())});
  }
  count_ = cells.size();
}

int ReachableCells::storeyOf(float z_units) { return static_cast<int>(std::floor(z_units / (2 * kStepHeightUnits))); }

std::optional<ReachableCells::CellStorey> ReachableCells::floorAt(const Eigen::Vector3d& world_units) const {
  const Cell2 key = metreCell(world_units.x(), world_units.y());
  const auto it = heights_.find(key);
  if (it == heights_.end()) return std::nullopt;
  for (float z : it->second)
    if (std::abs(world_units.z() - z) <= kStepHeightUnits / 2) return CellStorey{key, storeyOf(z)};
  return std::nullopt;
}

std::set<ReachableCells::CellStorey> ReachableCells::observedBy(const FusedKeyframe& keyframe, const Sim3& map_to_world,
                                                                double band) const {
  std::set<CellStorey> seen;
  for (const auto& p : keyframe.points) {
    if (std::abs(p.h) >= band) continue;
    const auto pair = floorAt(map_to_world.apply(p.position.cast<double>()) * quake3::kUnitsPerMetre);
    if (pair) seen.insert(*pair);
  }
  return seen;
}

std::set<ReachableCells::CellStorey> ReachableCells::inViewOf(const FrameTruth& frame, const CameraIntrinsics& k,
                                                              double band_units, int stride) const {
  std::set<CellStorey> seen;
  if (frame.depth_m.empty()) return seen;
  const Eigen::Isometry3d& pose = frame.camera_to_world;  // optical frame to BSP, game units
  for (int v = stride / 2; v < frame.depth_m.rows; v += stride) {
    const float* row = frame.depth_m.ptr<float>(v);
    for (int u = stride / 2; u < frame.depth_m.cols; u += stride) {
      const double d = row[u];
      if (!std::isfinite(d) || d <= 0) continue;  // NaN: sky
      const Eigen::Vector3d ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
      const Eigen::Vector3d world = pose * (d * quake3::kUnitsPerMetre * ray);
      if (std::abs(world.z() - frame.floor_z) >= band_units) continue;
      const auto pair = floorAt(world);
      if (pair) seen.insert(*pair);
    }
  }
  return seen;
}

namespace {

// The committed frames' estimated poses (map units) beside their true ones (BSP
// frame, metres), as many as both exist for.
struct CommittedPoses {
  std::vector<Eigen::Isometry3d> estimate, truth_metres;
};

CommittedPoses committedPoses(const Episode& episode) {
  CommittedPoses p;
  const size_t n = std::min(episode.trajectory().size(), episode.truth().size());
  p.estimate.assign(episode.trajectory().begin(), episode.trajectory().begin() + n);
  for (size_t i = 0; i < n; ++i) {
    Eigen::Isometry3d pose = episode.truth()[i].camera_to_world;
    pose.translation() /= quake3::kUnitsPerMetre;
    p.truth_metres.push_back(pose);
  }
  return p;
}

// alignEpisode on the episode's committed poses, already paired.
EpisodeAlignment alignPoses(const Episode& episode, const CommittedPoses& poses) {
  EpisodeAlignment a;
  if (poses.estimate.empty()) return a;
  const TrajectoryError ate = trajectoryError(poses.estimate, poses.truth_metres);
  a.aligned = ate.aligned;
  if (a.aligned) {
    a.map_to_world_metres = ate.alignment;
    a.rmse_m = ate.ate_rmse;
    a.ate_percent = ate.ate_percent;
    return a;
  }
  // Fused keyframes exist only where a floor was known, and the grid re-anchors on the
  // first reliable floor, so with a non-empty map kappa_0 is a measured floor distance.
  const double kappa = episode.anchorEyeHeight();
  if (episode.map().keyframes().empty() || !(kappa > 0) || !std::isfinite(kappa)) return a;
  const Eigen::Isometry3d& estimate0 = episode.trajectory().front();
  Sim3 floor_tie;
  floor_tie.scale = episode.config().world.eye_height_units / quake3::kUnitsPerMetre / kappa;
  floor_tie.rotation = poses.truth_metres.front().linear() * estimate0.linear().transpose();
  floor_tie.translation =
      poses.truth_metres.front().translation() - floor_tie.scale * (floor_tie.rotation * estimate0.translation());
  a.floor_aligned = true;
  a.map_to_world_metres = floor_tie;
  return a;
}

}  // namespace

EpisodeAlignment alignEpisode(const Episode& episode) { return alignPoses(episode, committedPoses(episode)); }

EpisodeTruth evaluateEpisodeTruth(const Episode& episode, const quake3::ReachableFloor& reachable) {
  EpisodeTruth t;
  const auto& truth = episode.truth();
  t.committed_frames = static_cast<int>(truth.size());
  const PenetrationCounts penetrations = countPenetrations(truth);
  t.penetrating_frames = penetrations.frames;
  t.penetrating_frames_in_solid = penetrations.in_solid;
  t.penetrating_frames_outside_world = penetrations.outside_world;
  t.penetrating_frames_clip_only = penetrations.clip_only;
  // The context frames are in the trajectory but in no step: a spawn is never in solid.
  t.discarded_penetrating_frames = committedInSolidFrames(episode.history()) - t.penetrating_frames;

  for (const auto& step : episode.history()) {
    for (const auto& c : step.candidates) {
      if (c.truth.empty()) continue;
      const bool enters_solid = !staysOutOfSolid(c);
      const bool predicted = c.verdict.predictsCollision();
      ++t.verdicts;
      t.truly_colliding += enters_solid;
      t.predicted_colliding += predicted;
      t.false_rejections += predicted && !enters_solid;
      t.missed_collisions += enters_solid && !predicted;
    }
  }

  const ReachableCells cells(reachable);
  t.reachable_m2 = static_cast<double>(cells.count());
  const Config& config = episode.config();
  const CameraIntrinsics k =
      CameraIntrinsics::fromHorizontalFov(config.world.width, config.world.height, config.world.fov_x_deg);
  std::set<ReachableCells::CellStorey> in_view;
  for (const FrameTruth& frame : truth) {
    const auto seen = cells.inViewOf(frame, k, config.collision.height_low * config.world.eye_height_units,
                                     config.slam.cloud_stride_px);
    in_view.insert(seen.begin(), seen.end());
  }
  t.in_view_reachable_m2 = static_cast<double>(in_view.size());
  t.in_view_reachable_percent = t.reachable_m2 > 0 ? 100.0 * t.in_view_reachable_m2 / t.reachable_m2 : 0;
  const CommittedPoses poses = committedPoses(episode);
  const EpisodeAlignment alignment = alignPoses(episode, poses);
  if (!alignment.aligned && !alignment.floor_aligned) return t;
  t.aligned = alignment.aligned;
  t.floor_aligned = alignment.floor_aligned;
  t.map_to_world_metres = alignment.map_to_world_metres;
  t.alignment_rmse_m = alignment.rmse_m;
  t.ate_percent = alignment.ate_percent;
  t.alignment_scale = t.map_to_world_metres.scale;
  // Roll and pitch errors of the committed frames; the BSP's up is +z.
  const std::vector<double> tilts =
      tiltErrorsDeg(poses.estimate, poses.truth_metres, t.map_to_world_metres.rotation, Eigen::Vector3d::UnitZ());
  t.tilt_median_deg = quantile(tilts, 0.5);
  t.tilt_p90_deg = quantile(tilts, 0.9);

  // Cells each keyframe observes, then their union over growing prefixes of the map.
  const double band = episode.config().collision.height_low;
  const auto& keyframes = episode.map().keyframes();
  std::vector<std::set<ReachableCells::CellStorey>> seen_by(keyframes.size());
  for (size_t k = 0; k < keyframes.size(); ++k) seen_by[k] = cells.observedBy(*keyframes[k], t.map_to_world_metres, band);
  std::set<ReachableCells::CellStorey> observed;
  size_t merged = 0;
  auto percent = [&] { return t.reachable_m2 > 0 ? 100.0 * observed.size() / t.reachable_m2 : 0.0; };
  for (const auto& step : episode.history()) {
    for (; merged < std::min(step.map_keyframes, keyframes.size()); ++merged)
      observed.insert(seen_by[merged].begin(), seen_by[merged].end());
    t.observed_percent_by_step.push_back(percent());
  }
  for (; merged < keyframes.size(); ++merged) observed.insert(seen_by[merged].begin(), seen_by[merged].end());
  t.observed_reachable_m2 = static_cast<double>(observed.size());
  t.observed_reachable_percent = t.reachable_m2 > 0 ? 100.0 * t.observed_reachable_m2 / t.reachable_m2 : 0;
  return t;
}

}  // namespace valerant
