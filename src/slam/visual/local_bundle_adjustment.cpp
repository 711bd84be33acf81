#include "valerant/slam/visual/local_bundle_adjustment.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <array>

namespace valerant::visual {
namespace {

// Pose block: map_to_camera as angle-axis (3) + translation (3).
using PoseBlock = std::array<double, 6>;

struct ReprojectionError {
  ReprojectionError(const Eigen::Vector2d& px, const CameraIntrinsics& k) : px_(px), k_(k) {}
  template <typename T>
  bool operator()(const T* pose, const T* point, T* residual) const {
    T p[3];
    ceres::AngleAxisRotatePoint(pose, point, p);
    for (int i = 0; i < 3; ++i) p[i] += pose[3 + i];
    // Points that slip behind the camera are caught by the error check afterwards.
    const T z = p[2] > T(1e-6) ? p[2] : T(1e-6);
    residual[0] = T(k_.fx) * p[0] / z + T(k_.cx) - T(px_.x());
    residual[1] = T(k_.fy) * p[1] / z + T(k_.cy) - T(px_.y());
    return true;
  }
  Eigen::Vector2d px_;
  CameraIntrinsics k_;
};

PoseBlock toBlock(const Eigen::Isometry3d& camera_to_map) {
  const Eigen::Isometry3d m = camera_to_map.inverse();
  const Eigen::AngleAxisd aa(m.linear());
  const Eigen::Vector3d r = aa.axis() * aa.angle();
  return {r.x(), r.y(), r.z(), m.translation().x(), m.translation().y(), m.translation().z()};
}

Eigen::Isometry3d fromBlock(const PoseBlock& b) {
  const Eigen::Vector3d r(b[0], b[1], b[2]);
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  if (r.norm() > 0) m.linear() = Eigen::AngleAxisd(r.norm(), r.normalized()).toRotationMatrix();
  m.translation() = Eigen::Vector3d(b[3], b[4], b[5]);
  return m.inverse();
}

}  // namespace

BundleAdjustmentResult localBundleAdjustment(const std::map<int, Eigen::Isometry3d>& poses,
                                             const std::set<int>& free,
                                             const std::map<int, const MapPoint*>& points,
                                             const CameraIntrinsics& k, const BundleAdjustmentParams& params) {
  std::map<int, PoseBlock> pose_blocks;
  for (const auto& [index, pose] : poses) pose_blocks[index] = toBlock(pose);
  std::map<int, Eigen::Vector3d> positions;
  for (const auto& [id, point] : points) positions[id] = point->position;

  ceres::Problem problem;
  for (const auto& [id, point] : points) {
    for (const Observation& o : point->observations) {
      auto it = pose_blocks.find(o.keyframe);
      if (it == pose_blocks.end()) continue;
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<ReprojectionError, 2, 6, 3>(new ReprojectionError(o.px, k)),
          new ceres::HuberLoss(params.huber_px), it->second.data(), positions[id].data());
    }
  }
  for (auto& [index, block] : pose_blocks)
    if (problem.HasParameterBlock(block.data()) && !free.count(index)) problem.SetParameterBlockConstant(block.data());

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_SCHUR;
  options.max_num_iterations = params.max_iterations;
  options.num_threads = 1;  // determinism and the one-core-per-branch budget
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);

  BundleAdjustmentResult out;
  for (int index : free) {
    auto it = pose_blocks.find(index);
    if (it != pose_blocks.end()) out.poses[index] = fromBlock(it->second);
  }
  for (const auto& [id, point] : points) {
    const Eigen::Vector3d& p = positions[id];
    bool good = p.allFinite();
    for (const Observation& o : point->observations) {
      auto it = pose_blocks.find(o.keyframe);
      if (!good || it == pose_blocks.end()) continue;
      const Eigen::Vector3d c = fromBlock(it->second).inverse() * p;
      const double err = c.z() <= 0 ? 1e9
                                    : (Eigen::Vector2d(k.fx * c.x() / c.z() + k.cx, k.fy * c.y() / c.z() + k.cy) - o.px)
                                          .norm();
      good = err <= params.max_error_px;
    }
    if (good)
      out.points[id] = p;
    else
      out.rejected.push_back(id);
  }
  return out;
}

}  // namespace valerant::visual
