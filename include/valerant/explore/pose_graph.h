#pragma once
// The keyframe pose graph of loop closure, optimised with Ceres: each node is a
// keyframe's camera-to-map similarity S_i, each edge a measured relative transform
// Z_ij ~ S_i^-1 S_j (odometry between consecutive committed keyframes, or a verified
// loop). Residual of an edge, E = Z_ij^-1 S_i^-1 S_j:
//   translation of E / translation_unit (3), rotation of E as angle-axis (3),
//   ln(scale of E) (1, only when scale is estimated),
// all with unit weight, as ORB-SLAM's essential graph weighs its edges. A monocular
// SLAM drifts in scale, so its graph is Sim(3) (estimate_scale); a metric one keeps
// every scale at 1 (SE(3)). Node 0 is held fixed: it fixes the map frame (gauge).
//
// [ours] Scale priors (loop_closure.eye_height_weight): a node i with a target tau_i
// adds the residual w (ln s_i - tau_i), under a Huber loss past w ln 1.5, so that one
// keyframe whose floor was another storey's does not pull the graph. LoopClosure sets
// tau_i = ln(kappa_0 / kappa_i): the scale at which its eye stands kappa_0 over its floor.
//
// [ours] Level priors (loop_closure.level_weight): a node i with u_i, its floor's unit
// normal in camera coordinates, adds the residual w (R_i u_i - g) (3), g the map's up
// (the anchor floor's normal), under a Huber loss past w 2 sin(3 deg / 2): a keyframe on
// a ramp does not tilt the graph. Its norm is w 2 sin(theta / 2), theta the angle by which
// the node's floor stands off level. A monocular SLAM drifts in roll and pitch too, and
// every keyframe's floor measures its own.
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "valerant/geometry/similarity3.h"

namespace valerant {

struct PoseGraphEdge {
  size_t from = 0, to = 0;
  Similarity3 relative;  // measured S_from^-1 S_to
};

struct PoseGraphOptions {
  bool estimate_scale = true;
  double translation_unit = 1;  // map units of one unit of translation residual (the eye height)
  int max_iterations = 50;
  // One target ln(scale) per node (NaN: none) or empty; used with estimate_scale and a
  // positive weight.
  std::vector<double> log_scale_targets;
  double scale_prior_weight = 0;
  // One floor normal in camera coordinates per node (zero: none) or empty, and the map's
  // up; used with a positive weight.
  std::vector<Eigen::Vector3d> floor_normals_in_camera;
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double level_prior_weight = 0;
};

// The Huber corner of a level prior, as an angle off level.
constexpr double kLevelPriorCornerDeg = 3.0;

struct PoseGraphSolution {
  std::vector<Similarity3> nodes;  // optimised, one per initial node
  bool converged = false;          // Ceres met a convergence tolerance within max_iterations
};

// The optimised nodes; `initial` (at least one) is the starting point. Throws
// InputError for an edge naming a node that does not exist, or scale targets or floor
// normals that are not one per node.
PoseGraphSolution optimisePoseGraph(const std::vector<Similarity3>& initial, const std::vector<PoseGraphEdge>& edges,
                                    const PoseGraphOptions& options);

}  // namespace valerant
