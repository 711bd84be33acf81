#include "valerant/eval/episode_truth.h"

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <set>

namespace valerant {
namespace {

constexpr double kUnitsPerMetre = 32.0;
constexpr double kStepHeightUnits = 18.0;  // Quake III STEPSIZE
// Below this spread (metres) a Sim(3) fit of the trajectory is meaningless.
constexpr double kMinAlignmentSpreadMetres = 0.5;

using Cell2 = std::pair<int, int>;

Cell2 metreCell(double x_units, double y_units) {
  return {static_cast<int>(std::floor(x_units / kUnitsPerMetre)), static_cast<int>(std::floor(y_units / kUnitsPerMetre))};
}

}  // namespace

bool alignTrajectory(const std::vector<Eigen::Vector3d>& map_centres, const std::vector<Eigen::Vector3d>& truth_centres,
                     Eigen::Matrix4d& map_to_world) {
  const size_t n = std::min(map_centres.size(), truth_centres.size());
  if (n < 3) return false;
  Eigen::Matrix3Xd src(3, n), dst(3, n);
  for (size_t i = 0; i < n; ++i) {
    src.col(i) = map_centres[i];
    dst.col(i) = truth_centres[i];
  }
  const Eigen::Vector3d mean = dst.rowwise().mean();
  const double spread = std::sqrt((dst.colwise() - mean).squaredNorm() / n);
  if (spread < kMinAlignmentSpreadMetres) return false;
  map_to_world = Eigen::umeyama(src, dst, true);
  return map_to_world.allFinite();
}

EpisodeTruth evaluateEpisodeTruth(const Episode& episode, const quake3::ReachableFloor& reachable) {
  EpisodeTruth t;
  const auto& truth = episode.truth();
  t.committed_frames = static_cast<int>(truth.size());
  for (const auto& f : truth) t.penetrating_frames += f.in_solid;

  for (const auto& step : episode.history()) {
    for (const auto& c : step.candidates) {
      if (c.truth.empty()) continue;
      bool enters_solid = false;
      for (const auto& f : c.truth) enters_solid |= f.in_solid;
      const bool predicted = c.verdict.collision_pc || c.verdict.collision_depth;
      ++t.verdicts;
      t.truly_colliding += enters_solid;
      t.predicted_colliding += predicted;
      t.false_rejections += predicted && !enters_solid;
      t.missed_collisions += enters_solid && !predicted;
    }
  }

  // Reachable 1 m cells, each with the floor heights found in it.
  std::map<Cell2, std::vector<float>> reachable_heights;
  std::set<std::pair<Cell2, int>> reachable_cells;  // (cell, storey) pairs
  for (const auto& c : reachable.cells) {
    const Cell2 key = metreCell(c.x(), c.y());
    reachable_heights[key].push_back(c.z());
    reachable_cells.insert({key, static_cast<int>(std::floor(c.z() / (2 * kStepHeightUnits)))});
  }
  t.reachable_m2 = static_cast<double>(reachable_cells.size());

  std::vector<Eigen::Vector3d> map_centres, truth_centres;
  const auto& trajectory = episode.trajectory();
  for (size_t i = 0; i < std::min(trajectory.size(), truth.size()); ++i) {
    map_centres.push_back(trajectory[i].translation());
    truth_centres.push_back(truth[i].camera_to_world.translation() / kUnitsPerMetre);
  }
  Eigen::Matrix4d map_to_world;
  t.aligned = alignTrajectory(map_centres, truth_centres, map_to_world);
  if (!t.aligned) return t;
  t.alignment_scale = map_to_world.block<3, 3>(0, 0).col(0).norm();
  double residual = 0;
  for (size_t i = 0; i < map_centres.size(); ++i)
    residual += ((map_to_world * map_centres[i].homogeneous()).head<3>() - truth_centres[i]).squaredNorm();
  t.alignment_rmse_m = std::sqrt(residual / map_centres.size());

  std::set<std::pair<Cell2, int>> observed;
  const double band = episode.config().collision.height_low;
  for (const auto& kf : episode.map().keyframes()) {
    for (const auto& p : kf->points) {
      if (std::abs(p.h) >= band) continue;
      const Eigen::Vector3d world = (map_to_world * p.position.cast<double>().homogeneous()).head<3>() * kUnitsPerMetre;
      const Cell2 key = metreCell(world.x(), world.y());
      auto it = reachable_heights.find(key);
      if (it == reachable_heights.end()) continue;
      for (float z : it->second) {
        if (std::abs(world.z() - z) <= kStepHeightUnits / 2) {
          observed.insert({key, static_cast<int>(std::floor(z / (2 * kStepHeightUnits)))});
          break;
        }
      }
    }
  }
  t.observed_reachable_m2 = static_cast<double>(observed.size());
  t.observed_reachable_percent = t.reachable_m2 > 0 ? 100.0 * t.observed_reachable_m2 / t.reachable_m2 : 0;
  return t;
}

}  // namespace valerant
