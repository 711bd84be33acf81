#include "valerant/explore/pose_graph.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <array>
#include <cmath>
#include <string>

#include "valerant/common/error.h"

namespace valerant {
namespace {

// One node's parameters: rotation quaternion (Eigen order x y z w), translation,
// ln(scale); kept apart so the quaternion gets its manifold and ln(scale) can be held.
struct NodeBlocks {
  std::array<double, 4> rotation;
  std::array<double, 3> translation;
  double log_scale;
};

struct EdgeResidual {
  EdgeResidual(const Similarity3& z, double unit, bool with_scale)
      : z_inverse_(z.inverse()), unit_(unit), with_scale_(with_scale) {}

  template <typename T>
  bool operator()(const T* qi, const T* ti, const T* si, const T* qj, const T* tj, const T* sj, T* residual) const {
    using Quat = Eigen::Quaternion<T>;
    using Vec = Eigen::Matrix<T, 3, 1>;
    const Eigen::Map<const Quat> ri(qi), rj(qj);
    const Eigen::Map<const Vec> pi(ti), pj(tj);
    // P = S_i^-1 S_j: scale s_j / s_i, rotation R_i^T R_j, translation R_i^T (t_j - t_i) / s_i.
    const T log_p = sj[0] - si[0];
    const Quat rp = ri.conjugate() * rj;
    const Vec tp = (ri.conjugate() * (pj - pi)) * ceres::exp(-si[0]);
    // E = Z^-1 P.
    const Quat zr = z_inverse_.rotation.cast<T>();
    const Quat re = zr * rp;
    const Vec te = T(z_inverse_.scale) * (zr * tp) + z_inverse_.translation.cast<T>();
    for (int k = 0; k < 3; ++k) residual[k] = te[k] / T(unit_);
    const T q[4] = {re.w(), re.x(), re.y(), re.z()};  // ceres order: w x y z
    ceres::QuaternionToAngleAxis(q, residual + 3);
    residual[6] = with_scale_ ? log_p + T(std::log(z_inverse_.scale)) : T(0);
    return true;
  }

  Similarity3 z_inverse_;
  double unit_;
  bool with_scale_;
};

struct ScalePriorResidual {
  ScalePriorResidual(double target, double weight) : target_(target), weight_(weight) {}
  template <typename T>
  bool operator()(const T* log_scale, T* residual) const {
    residual[0] = T(weight_) * (log_scale[0] - T(target_));
    return true;
  }
  double target_, weight_;
};

struct LevelPriorResidual {
  LevelPriorResidual(const Eigen::Vector3d& normal_in_camera, const Eigen::Vector3d& up, double weight)
      : normal_(normal_in_camera), up_(up), weight_(weight) {}
  template <typename T>
  bool operator()(const T* q, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> r(q);
    const Eigen::Matrix<T, 3, 1> off = r * normal_.cast<T>() - up_.cast<T>();
    for (int k = 0; k < 3; ++k) residual[k] = T(weight_) * off[k];
    return true;
  }
  Eigen::Vector3d normal_, up_;
  double weight_;
};

}  // namespace

PoseGraphSolution optimisePoseGraph(const std::vector<Similarity3>& initial, const std::vector<PoseGraphEdge>& edges,
                                    const PoseGraphOptions& options) {
  if (initial.empty()) throw InputError("pose graph", "has no node");
  if (!options.log_scale_targets.empty() && options.log_scale_targets.size() != initial.size())
    throw InputError("pose graph scale targets", std::to_string(options.log_scale_targets.size()) + " for " +
                                                     std::to_string(initial.size()) + " nodes");
  if (!options.floor_normals_in_camera.empty() && options.floor_normals_in_camera.size() != initial.size())
    throw InputError("pose graph floor normals", std::to_string(options.floor_normals_in_camera.size()) + " for " +
                                                     std::to_string(initial.size()) + " nodes");
  std::vector<NodeBlocks> nodes(initial.size());
  for (size_t i = 0; i < initial.size(); ++i) {
    const Similarity3& s = initial[i];
    nodes[i].rotation = {s.rotation.x(), s.rotation.y(), s.rotation.z(), s.rotation.w()};
    nodes[i].translation = {s.translation.x(), s.translation.y(), s.translation.z()};
    nodes[i].log_scale = std::log(s.scale);
  }
  ceres::Problem problem;
  for (const PoseGraphEdge& e : edges) {
    if (e.from >= nodes.size() || e.to >= nodes.size() || e.from == e.to)
      throw InputError("pose graph edge " + std::to_string(e.from) + " -> " + std::to_string(e.to),
                       "names no pair of distinct nodes of " + std::to_string(nodes.size()));
    NodeBlocks& a = nodes[e.from];
    NodeBlocks& b = nodes[e.to];
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<EdgeResidual, 7, 4, 3, 1, 4, 3, 1>(
                                 new EdgeResidual(e.relative, options.translation_unit, options.estimate_scale)),
                             nullptr, a.rotation.data(), a.translation.data(), &a.log_scale, b.rotation.data(),
                             b.translation.data(), &b.log_scale);
  }
  const bool priors = options.estimate_scale && options.scale_prior_weight > 0;
  for (size_t i = 1; priors && i < options.log_scale_targets.size(); ++i) {
    const double target = options.log_scale_targets[i];
    if (!std::isfinite(target) || !problem.HasParameterBlock(&nodes[i].log_scale)) continue;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ScalePriorResidual, 1, 1>(
                                 new ScalePriorResidual(target, options.scale_prior_weight)),
                             new ceres::HuberLoss(options.scale_prior_weight * std::log(1.5)), &nodes[i].log_scale);
  }
  const double level_corner = options.level_prior_weight * 2 * std::sin(kLevelPriorCornerDeg * M_PI / 360);
  for (size_t i = 1; options.level_prior_weight > 0 && i < options.floor_normals_in_camera.size(); ++i) {
    const Eigen::Vector3d& normal = options.floor_normals_in_camera[i];
    if (normal.isZero() || !problem.HasParameterBlock(nodes[i].rotation.data())) continue;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<LevelPriorResidual, 3, 4>(
                                 new LevelPriorResidual(normal.normalized(), options.up.normalized(), options.level_prior_weight)),
                             new ceres::HuberLoss(level_corner), nodes[i].rotation.data());
  }
  for (size_t i = 0; i < nodes.size(); ++i) {
    NodeBlocks& n = nodes[i];
    if (!problem.HasParameterBlock(n.rotation.data())) continue;  // a node no edge reaches stays as it is
    problem.SetManifold(n.rotation.data(), new ceres::EigenQuaternionManifold);
    if (i == 0) {
      problem.SetParameterBlockConstant(n.rotation.data());
      problem.SetParameterBlockConstant(n.translation.data());
    }
    if (i == 0 || !options.estimate_scale) problem.SetParameterBlockConstant(&n.log_scale);
  }
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver.max_num_iterations = options.max_iterations;
  solver.num_threads = 1;  // determinism
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);

  PoseGraphSolution solution;
  solution.converged = summary.termination_type == ceres::CONVERGENCE;
  std::vector<Similarity3>& out = solution.nodes;
  out.resize(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i) {
    const NodeBlocks& n = nodes[i];
    out[i].rotation = Eigen::Quaterniond(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]).normalized();
    out[i].translation = Eigen::Vector3d(n.translation[0], n.translation[1], n.translation[2]);
    out[i].scale = std::exp(n.log_scale);
  }
  return solution;
}

}  // namespace valerant
