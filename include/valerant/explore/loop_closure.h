#pragma once
// Loop closure over the committed keyframes [ours] (docs/loop_closure.md). The SLAM
// keeps running in its own frame as odometry; this keeps the pose graph of every
// committed keyframe (nodes in commit order, odometry edges between consecutive ones
// from the SLAM's poses, loop edges from verified matches) and each keyframe's
// correction C_i = S_i T_i^-1 from the SLAM frame to the corrected map frame (S_i its
// optimised pose, T_i its SLAM pose). A committed keyframe is compared with the older
// keyframes (at least min_age_keyframes before it) whose corrected camera centre is
// near its predicted one (the latest correction applied to its SLAM pose) and whose
// view direction is close; the nearest few are verified (loop_verifier.h). Each
// verified match adds a loop edge; a commit that added any optimises the graph
// (pose_graph.h) and rewrites the map and trajectory from the new corrections.
// Frames take the correction of the latest keyframe at or before them. A map keyframe is
// a corrected copy; [ours] a new correction that moves none of its points by more than
// rewrite_tolerance_eye_heights keeps the copy it has, so a correction that moves only
// the recent map copies only that (each copy is memory, and checkpoints keep theirs).
//
// [ours] The eye height (loop_closure.eye_height_weight > 0, a Sim(3) graph): each node
// also keeps its keyframe's camera-to-floor distance kappa_i in SLAM units, and the graph
// holds its scale to kappa_0 / kappa_i (pose_graph.h). A commit whose new keyframes
// stand, by the latest correction, more than eye_height_tolerance off kappa_0 (their
// median) optimises and rewrites the map as a closure does (a scale correction): the
// visual SLAM's scale drifts, and the floor under each keyframe measures by how much.
//
// [ours] Level (loop_closure.level_weight > 0): each node with a floor fitted on it also
// keeps that floor's normal in camera coordinates, and the graph holds its roll and pitch
// so that the normal points along the anchor floor's (pose_graph.h). A commit whose new
// keyframes' floors stand, by the latest correction, more than level_tolerance_deg off
// level (their median) optimises and rewrites the map too (a level correction).
//
// Only commits reach it, so candidate branches never close loops; a copy of it is
// part of every checkpoint, so a rewind to before a closure undoes the closure.
#include <Eigen/Geometry>
#include <limits>
#include <memory>
#include <vector>

#include "valerant/common/camera.h"
#include "valerant/config/config.h"
#include "valerant/explore/branch_pipeline.h"
#include "valerant/explore/keyframe_features.h"
#include "valerant/explore/loop_verifier.h"
#include "valerant/explore/pose_graph.h"
#include "valerant/geometry/floor_plane.h"
#include "valerant/geometry/similarity3.h"
#include "valerant/map/map_fusion.h"

namespace valerant {

// One verified candidate, made or rejected.
struct LoopClosureRecord {
  int step = 0;                 // committed step that brought the new keyframe (0: the context)
  size_t new_keyframe = 0;      // pose graph nodes: committed keyframes in commit order
  size_t old_keyframe = 0;
  LoopVerification verification;
};

class LoopClosure {
 public:
  // `estimate_scale`: a Sim(3) graph for a monocular SLAM, SE(3) for a metric one.
  LoopClosure(const LoopClosureConfig& config, const CameraIntrinsics& intrinsics, bool estimate_scale);

  // After the episode fused `result`'s keyframes of known floor into `map` (its last
  // ones) and appended its poses to `trajectory`, both as the SLAM made them: maps them
  // into the corrected frame, looks for loops from its keyframes and, when it found
  // any, optimises and rewrites all of `map` and `trajectory`; so do scale and level
  // corrections. `anchor`: the episode's anchor floor in the map frame, whose camera
  // height is one eye height (kappa_0) and whose normal is up. Returns true when earlier
  // keyframes and frames moved.
  bool commit(const BranchResult& result, int step, const FloorPlane& anchor, MapFusion& map,
              std::vector<Eigen::Isometry3d>& trajectory);
  // Puts this state's map and trajectory back into the episode's (after a rewind).
  void restoreInto(MapFusion& map, std::vector<Eigen::Isometry3d>& trajectory) const;
  // [ours] dead_pocket.keep_map: this state (a checkpoint's) also keeps the keyframes that
  // `left`, the state a rewind leaves and a descendant of this one, fused after it. They
  // are no graph nodes: each rides on the latest node this state has (the rewind's anchor,
  // whose SLAM state they descend from) or on its own node where this state still holds it.
  void keepKeyframesOf(const LoopClosure& left);
  // Closures, scale and level corrections made so far: a state that made more has moved the map.
  size_t corrections() const { return loops_.size() + scale_corrections_ + level_corrections_; }

  // SLAM-frame poses in the corrected map frame, by the latest correction.
  std::vector<Eigen::Isometry3d> toMap(const std::vector<Eigen::Isometry3d>& slam_poses) const;

  const std::vector<LoopClosureRecord>& records() const { return records_; }
  // The committed frames' poses as the SLAM made them (the trajectory without closures).
  const std::vector<Eigen::Isometry3d>& odometry() const { return odometry_; }
  size_t made() const { return loops_.size(); }
  // Commits that optimised the graph for the eye height alone.
  size_t scaleCorrections() const { return scale_corrections_; }
  // Commits that optimised the graph for level alone.
  size_t levelCorrections() const { return level_corrections_; }
  // Graph optimisations so far, and those Ceres ended without converging (max_iterations).
  size_t optimisations() const { return optimisations_; }
  size_t unconvergedOptimisations() const { return unconverged_; }
  // Corrected copies of map keyframes made so far (a keyframe no correction moves has none).
  size_t keyframesRewritten() const { return keyframes_rewritten_; }
  size_t keyframes() const { return nodes_.size(); }
  // The correction of a committed keyframe (pose graph node).
  const Similarity3& correction(size_t keyframe) const { return nodes_.at(keyframe).correction; }

 private:
  struct Node {
    Eigen::Isometry3d odometry;  // the SLAM's camera_to_map
    Similarity3 correction;             // SLAM frame -> map frame
    std::shared_ptr<const KeyframeFeatures> features;  // null without an image
    double kappa = std::numeric_limits<double>::quiet_NaN();  // camera-to-floor, SLAM units; NaN: floor unknown
    Eigen::Vector3d floor_normal = Eigen::Vector3d::Zero();  // camera coordinates; zero: no floor fitted on it
  };
  Similarity3 pose(size_t node) const { return nodes_[node].correction * Similarity3::fromIsometry(nodes_[node].odometry); }
  Similarity3 latestCorrection() const { return nodes_.empty() ? Similarity3{} : nodes_.back().correction; }
  // A map keyframe: as fused in the SLAM frame; as in the map, by `applied`; the box of
  // its map points and camera centre, over which a new correction's move is bounded; its
  // node (-1: before the first node, never corrected).
  struct MapKeyframe {
    std::shared_ptr<const FusedKeyframe> fused, corrected;
    Similarity3 applied;
    Eigen::AlignedBox3d extent;
    long node = -1;
  };
  const Similarity3& frameCorrection(size_t frame) const;
  const Similarity3& nodeCorrection(long node) const;
  // Brings `keyframe`'s map copy to its node's correction: a new copy unless the
  // correction moves the one it has by at most the tolerance.
  void correct(MapKeyframe& keyframe);
  // Verifies the candidates of node `j`; true when one became a loop edge.
  bool detect(size_t j, int step, double eye_height);
  void optimise(double eye_height);
  // Whether the nodes from `first` stand off `eye_height` by more than the tolerance.
  bool scaleDrifted(size_t first, double eye_height) const;
  // Whether the nodes from `first` stand off level by more than the tolerance.
  bool levelDrifted(size_t first) const;
  // Rewrites map keyframes from `first_keyframe` and frames from `first_frame`.
  void rewrite(size_t first_keyframe, size_t first_frame, MapFusion& map, std::vector<Eigen::Isometry3d>& trajectory);

  LoopClosureConfig config_;
  CameraIntrinsics intrinsics_;
  bool estimate_scale_;
  std::vector<Node> nodes_;
  std::vector<PoseGraphEdge> loops_;
  size_t scale_corrections_ = 0;
  size_t level_corrections_ = 0;
  size_t optimisations_ = 0;
  size_t unconverged_ = 0;
  size_t keyframes_rewritten_ = 0;
  double eye_height_ = 0;  // kappa_0 of the last commit, in map units: the tolerance's unit
  Eigen::Vector3d up_ = Eigen::Vector3d::Zero();  // the anchor floor's normal (zero: unknown, no level)
  std::vector<LoopClosureRecord> records_;
  std::vector<MapKeyframe> keyframes_;  // aligned with the episode's map
  // Aligned with the episode's trajectory: SLAM poses and the node each follows (-1:
  // before the first keyframe, never corrected: node 0 is the graph's fixed gauge).
  std::vector<Eigen::Isometry3d> odometry_;
  std::vector<long> frame_nodes_;
};

}  // namespace valerant
