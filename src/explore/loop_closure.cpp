#include "valerant/explore/loop_closure.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "valerant/common/error.h"
#include "valerant/common/median.h"
#include "valerant/map/corrected_keyframe.h"

namespace valerant {
namespace {

bool isIdentity(const Similarity3& s) {
  const Similarity3 identity;
  return s.scale == identity.scale && s.rotation.coeffs() == identity.rotation.coeffs() &&
         s.translation == identity.translation;
}

}  // namespace

LoopClosure::LoopClosure(const LoopClosureConfig& config, const CameraIntrinsics& intrinsics, bool estimate_scale)
    : config_(config), intrinsics_(intrinsics), estimate_scale_(estimate_scale) {}

const Similarity3& LoopClosure::nodeCorrection(long node) const {
  static const Similarity3 identity;
  return node < 0 ? identity : nodes_[node].correction;
}

const Similarity3& LoopClosure::frameCorrection(size_t frame) const { return nodeCorrection(frame_nodes_[frame]); }

void LoopClosure::correct(MapKeyframe& keyframe) {
  const Similarity3& c = nodeCorrection(keyframe.node);
  const double tolerance = config_.rewrite_tolerance_eye_heights * eye_height_;
  if (keyframe.corrected && (c * keyframe.applied.inverse()).maxDisplacement(keyframe.extent) <= tolerance) return;
  if (isIdentity(c)) {
    keyframe.corrected = keyframe.fused;
  } else {
    keyframe.corrected = correctedKeyframe(*keyframe.fused, c);
    ++keyframes_rewritten_;
  }
  keyframe.applied = c;
  keyframe.extent = Eigen::AlignedBox3d(keyframe.corrected->camera_to_map.translation());
  for (const FusedPoint& p : keyframe.corrected->points) keyframe.extent.extend(p.position.cast<double>());
}

bool LoopClosure::commit(const BranchResult& result, int step, const FloorPlane& anchor, MapFusion& map,
                         std::vector<Eigen::Isometry3d>& trajectory) {
  const std::string what = "loop closure at step " + std::to_string(step);
  if (trajectory.size() != odometry_.size() + result.poses.size())
    throw InputError(what, "the trajectory does not end with the committed poses");
  if (result.keyframes.size() != result.keyframe_floors.size())
    throw InputError(what, "keyframes and floors differ in length");
  const size_t first_frame = odometry_.size();
  const size_t first_keyframe = keyframes_.size();
  const double eye_height = anchor.cameraHeight();
  eye_height_ = eye_height;
  up_ = anchor.known ? anchor.n.normalized() : Eigen::Vector3d::Zero();
  const size_t first_node = nodes_.size();
  const Similarity3 before = latestCorrection();

  // Keyframes: nodes, and the map's new ones (those of known floor, in order).
  std::vector<long> node_at_frame(result.poses.size(), -1);
  size_t map_index = first_keyframe;
  for (size_t r = 0; r < result.keyframes.size(); ++r) {
    const KeyframeCloud& kf = result.keyframes[r];
    Node node{kf.camera_to_map, before, nullptr};
    // A turn in place has no baseline: its keyframes' floors rest on the depth prior and
    // the map it sweeps against, so they measure neither scale nor level (on oa_dm5 one
    // turn's correction undid half the floor observed, docs/floor_in_view.md).
    const FloorPlane& floor = result.keyframe_floors[r];
    const bool measures = floor.known && !result.verdict.rotation_only;
    if (measures) node.kappa = floor.cameraHeight();
    if (measures && floor.reliable) node.floor_normal = kf.camera_to_map.linear().transpose() * floor.n.normalized();
    const long local = static_cast<long>(kf.frame) - static_cast<long>(first_frame);
    if (local >= 0 && local < static_cast<long>(result.rollout.frames.size()))
      node.features = std::make_shared<const KeyframeFeatures>(
          describeKeyframe(result.rollout.frames[local], kf, intrinsics_, config_));
    if (local >= 0 && local < static_cast<long>(node_at_frame.size())) node_at_frame[local] = nodes_.size();
    if (result.keyframe_floors[r].known) {
      if (map_index >= map.marker()) throw InputError(what, "the map lacks the committed keyframes");
      MapKeyframe added;
      added.fused = map.keyframes()[map_index++];
      added.node = static_cast<long>(nodes_.size());
      keyframes_.push_back(std::move(added));
    }
    nodes_.push_back(std::move(node));
  }
  if (map_index != map.marker()) throw InputError(what, "the map holds keyframes the result did not make");
  // Frames follow the latest keyframe at or before them.
  long following = frame_nodes_.empty() ? -1 : frame_nodes_.back();
  for (size_t f = 0; f < result.poses.size(); ++f) {
    if (node_at_frame[f] >= 0) following = node_at_frame[f];
    odometry_.push_back(result.poses[f]);
    frame_nodes_.push_back(following);
  }

  bool closed = false;
  for (size_t j = first_node; j < nodes_.size(); ++j) closed |= detect(j, step, eye_height);
  const bool rescaled = !closed && scaleDrifted(first_node, eye_height);
  const bool levelled = !closed && !rescaled && levelDrifted(first_node);
  const bool moved = closed || rescaled || levelled;
  if (moved) optimise(eye_height);
  scale_corrections_ += rescaled;
  level_corrections_ += levelled;
  rewrite(moved ? 0 : first_keyframe, moved ? 0 : first_frame, map, trajectory);
  return moved;
}

bool LoopClosure::scaleDrifted(size_t first, double eye_height) const {
  if (!estimate_scale_ || !(config_.eye_height_weight > 0) || !(eye_height > 0)) return false;
  std::vector<double> off;  // |ln(corrected kappa / kappa_0)| of the new nodes
  for (size_t j = std::max<size_t>(first, 1); j < nodes_.size(); ++j)
    if (nodes_[j].kappa > 0) off.push_back(std::abs(std::log(pose(j).scale * nodes_[j].kappa / eye_height)));
  return !off.empty() && median(std::move(off)) > std::log(1 + config_.eye_height_tolerance);
}

bool LoopClosure::levelDrifted(size_t first) const {
  if (!(config_.level_weight > 0) || up_.isZero()) return false;
  std::vector<double> off;  // angle of the new nodes' corrected floor normals to up, degrees
  for (size_t j = std::max<size_t>(first, 1); j < nodes_.size(); ++j)
    if (!nodes_[j].floor_normal.isZero())
      off.push_back(std::acos(std::clamp((pose(j).rotation * nodes_[j].floor_normal).dot(up_), -1.0, 1.0)) * 180 / M_PI);
  return !off.empty() && median(std::move(off)) > config_.level_tolerance_deg;
}

bool LoopClosure::detect(size_t j, int step, double eye_height) {
  const Node& node = nodes_[j];
  if (!node.features || j < static_cast<size_t>(config_.min_age_keyframes)) return false;
  const Similarity3 predicted = pose(j);
  const Eigen::Vector3d axis = predicted.rotation * Eigen::Vector3d::UnitZ();
  const double cos_limit = std::cos(config_.max_view_angle_deg * M_PI / 180);
  std::vector<std::pair<double, size_t>> candidates;  // distance, node
  for (size_t i = 0; i + config_.min_age_keyframes <= j; ++i) {
    if (!nodes_[i].features || nodes_[i].features->withDepth() == 0) continue;
    const Similarity3 old = pose(i);
    const double distance = (old.translation - predicted.translation).norm();
    if (distance > config_.radius_eye_heights * eye_height) continue;
    if ((old.rotation * Eigen::Vector3d::UnitZ()).dot(axis) < cos_limit) continue;
    candidates.emplace_back(distance, i);
  }
  std::sort(candidates.begin(), candidates.end());
  if (candidates.size() > static_cast<size_t>(config_.max_candidates)) candidates.resize(config_.max_candidates);
  for (const auto& [distance, i] : candidates) {
    const Similarity3 old = pose(i);
    LoopClosureRecord record{step, j, i,
                             verifyLoop(*nodes_[i].features, *node.features, old.inverse() * predicted,
                                        eye_height / old.scale, estimate_scale_, intrinsics_, config_)};
    records_.push_back(record);
    if (record.verification.accepted) {
      loops_.push_back({i, j, record.verification.relative});
      return true;
    }
  }
  return false;
}

void LoopClosure::optimise(double eye_height) {
  std::vector<Similarity3> initial;
  std::vector<PoseGraphEdge> edges = loops_;
  for (size_t i = 0; i < nodes_.size(); ++i) {
    initial.push_back(pose(i));
    if (i > 0)
      edges.push_back(
          {i - 1, i, Similarity3::fromIsometry(nodes_[i - 1].odometry).inverse() * Similarity3::fromIsometry(nodes_[i].odometry)});
  }
  PoseGraphOptions options;
  options.estimate_scale = estimate_scale_;
  options.translation_unit = eye_height;
  options.max_iterations = config_.max_iterations;
  if (config_.eye_height_weight > 0 && eye_height > 0) {
    options.scale_prior_weight = config_.eye_height_weight;
    for (const Node& node : nodes_)
      options.log_scale_targets.push_back(node.kappa > 0 ? std::log(eye_height / node.kappa)
                                                         : std::numeric_limits<double>::quiet_NaN());
  }
  if (config_.level_weight > 0 && !up_.isZero()) {
    options.level_prior_weight = config_.level_weight;
    options.up = up_;
    for (const Node& node : nodes_) options.floor_normals_in_camera.push_back(node.floor_normal);
  }
  const PoseGraphSolution solution = optimisePoseGraph(initial, edges, options);
  ++optimisations_;
  unconverged_ += !solution.converged;
  const std::vector<Similarity3>& optimised = solution.nodes;
  for (size_t i = 0; i < nodes_.size(); ++i)
    nodes_[i].correction = optimised[i] * Similarity3::fromIsometry(nodes_[i].odometry).inverse();
}

void LoopClosure::rewrite(size_t first_keyframe, size_t first_frame, MapFusion& map,
                          std::vector<Eigen::Isometry3d>& trajectory) {
  for (size_t m = first_keyframe; m < keyframes_.size(); ++m) correct(keyframes_[m]);
  map.truncate(first_keyframe);
  for (size_t m = first_keyframe; m < keyframes_.size(); ++m) map.add(keyframes_[m].corrected);
  for (size_t f = first_frame; f < odometry_.size(); ++f) trajectory[f] = frameCorrection(f).applyTo(odometry_[f]);
}

void LoopClosure::restoreInto(MapFusion& map, std::vector<Eigen::Isometry3d>& trajectory) const {
  map.truncate(0);
  for (const MapKeyframe& kf : keyframes_) map.add(kf.corrected);
  trajectory.resize(odometry_.size());
  for (size_t f = 0; f < odometry_.size(); ++f) trajectory[f] = frameCorrection(f).applyTo(odometry_[f]);
}

void LoopClosure::keepKeyframesOf(const LoopClosure& left) {
  const auto same_fused = [](const MapKeyframe& a, const MapKeyframe& b) { return a.fused == b.fused; };
  if (left.keyframes_.size() < keyframes_.size() ||
      !std::equal(keyframes_.begin(), keyframes_.end(), left.keyframes_.begin(), same_fused))
    throw InputError("loop closure after a rewind", "the state left is no descendant of the checkpoint's");
  const long anchor = static_cast<long>(nodes_.size()) - 1;
  for (size_t m = keyframes_.size(); m < left.keyframes_.size(); ++m) {
    MapKeyframe kept = left.keyframes_[m];  // its copy stays where this state's correction allows
    kept.node = std::min(kept.node, anchor);
    correct(kept);
    keyframes_.push_back(std::move(kept));
  }
}

std::vector<Eigen::Isometry3d> LoopClosure::toMap(const std::vector<Eigen::Isometry3d>& slam_poses) const {
  const Similarity3 c = latestCorrection();
  if (isIdentity(c)) return slam_poses;
  std::vector<Eigen::Isometry3d> out;
  for (const auto& p : slam_poses) out.push_back(c.applyTo(p));
  return out;
}

}  // namespace valerant
