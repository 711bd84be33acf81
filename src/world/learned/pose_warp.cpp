#include "valerant/world/learned/pose_warp.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace valerant {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// Columns right, down, forward of the camera at `pose` in the floor frame
// (CameraKinematics::cameraToWorld's axes).
Eigen::Matrix3d cameraAxes(const CameraPose& pose) {
  const double a = pose.yaw_deg * kDegToRad, p = pose.pitch_deg * kDegToRad;
  Eigen::Matrix3d r;
  r.col(0) << std::sin(a), -std::cos(a), 0.0;
  r.col(1) << -std::sin(p) * std::cos(a), -std::sin(p) * std::sin(a), -std::cos(p);
  r.col(2) << std::cos(p) * std::cos(a), std::cos(p) * std::sin(a), -std::sin(p);
  return r;
}

// A point X in the optical frame of the camera at `from` is rotation X + translation in
// that of the camera at `to`.
struct RelativeTransform {
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
};

RelativeTransform relativeTransform(const CameraPose& to, const CameraPose& from) {
  const Eigen::Matrix3d to_t = cameraAxes(to).transpose();
  return {to_t * cameraAxes(from), to_t * Eigen::Vector3d(from.x_m - to.x_m, from.y_m - to.y_m, 0.0)};
}

Eigen::Vector3d ray(const CameraIntrinsics& camera, double x, double y) {
  return {(x + 0.5 - camera.cx) / camera.fx, (y + 0.5 - camera.cy) / camera.fy, 1.0};
}

}  // namespace

CameraPose advancePose(const CameraPose& pose, const MotionStep& motion) {
  CameraPose next = pose;
  next.yaw_deg = pose.yaw_deg + motion.yaw_deg;
  next.pitch_deg = pose.pitch_deg + motion.pitch_deg;
  const double heading = next.yaw_deg * kDegToRad;
  const double forward = motion.forward_units / kUnitsPerMetreWorld, strafe = motion.strafe_units / kUnitsPerMetreWorld;
  next.x_m = pose.x_m + forward * std::cos(heading) + strafe * std::sin(heading);
  next.y_m = pose.y_m + forward * std::sin(heading) - strafe * std::cos(heading);
  return next;
}

PoseGeometry PoseGeometry::start(const cv::Mat& depth_m, const CameraIntrinsics& camera) {
  CV_Assert(depth_m.type() == CV_32F);
  PoseGeometry g;
  g.depth.create(depth_m.size(), CV_32F);
  for (int y = 0; y < depth_m.rows; ++y)
    for (int x = 0; x < depth_m.cols; ++x) {
      const float d = depth_m.at<float>(y, x);
      g.depth.at<float>(y, x) = static_cast<float>(std::isfinite(d) ? std::max(static_cast<double>(d), kMinDepthM)
                                                                    : kSkyDepthM);
    }
  g.camera = camera;
  return g;
}

cv::Mat PoseGeometry::depthOf(const cv::Mat& coords) const {
  return depthInCamera(depth, coords, anchor_pose, pose, camera);
}

PoseGeometry PoseGeometry::moved(const MotionStep& motion) const {
  PoseGeometry g = *this;
  g.pose = advancePose(pose, motion);
  return g;
}

PoseGeometry PoseGeometry::reanchored(const cv::Mat& coords) const {
  PoseGeometry g = *this;
  g.depth = depthOf(coords);
  g.anchor_pose = pose;
  return g;
}

WarpSampling poseSampling(const cv::Mat& newest_depth, const CameraPose& newest_pose, const CameraPose& next_pose,
                          const CameraIntrinsics& camera) {
  CV_Assert(newest_depth.type() == CV_32F && newest_depth.cols == camera.width && newest_depth.rows == camera.height);
  const int w = camera.width, h = camera.height;
  const RelativeTransform m_to_n = relativeTransform(newest_pose, next_pose);
  const Eigen::Vector3d& t = m_to_n.translation;
  // Each pixel's ray turned into the newest camera, and whether it lies ahead of it.
  std::vector<Eigen::Vector3d> turned(static_cast<size_t>(w) * h);
  WarpSampling s{cv::Mat(h, w, CV_32FC2), cv::Mat(h, w, CV_32F)};
  const cv::Vec2f centre(0.5f * (w - 1), 0.5f * (h - 1));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector3d a = m_to_n.rotation * ray(camera, x, y);
      turned[static_cast<size_t>(y) * w + x] = a;
      s.positions.at<cv::Vec2f>(y, x) =
          a.z() > 1e-6 ? cv::Vec2f(static_cast<float>(camera.fx * a.x() / a.z() + camera.cx - 0.5),
                                   static_cast<float>(camera.fy * a.y() / a.z() + camera.cy - 0.5))
                       : centre;
    }
  cv::Mat depth_ahead(h, w, CV_32F, cv::Scalar(0));  // z' of the last iteration
  for (int iteration = 0; iteration < kPoseFixedPointIterations; ++iteration) {
    const cv::Mat depth = sampleBilinear(newest_depth, s.positions, false);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const Eigen::Vector3d& a = turned[static_cast<size_t>(y) * w + x];
        if (!(a.z() > 1e-6)) continue;
        const double z = std::max(static_cast<double>(depth.at<float>(y, x)), kMinDepthM);
        const double ahead = (z - t.z()) / a.z();
        depth_ahead.at<float>(y, x) = static_cast<float>(ahead);
        s.positions.at<cv::Vec2f>(y, x) =
            cv::Vec2f(static_cast<float>(camera.fx * (a.x() * ahead + t.x()) / z + camera.cx - 0.5),
                      static_cast<float>(camera.fy * (a.y() * ahead + t.y()) / z + camera.cy - 0.5));
      }
  }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const cv::Vec2f p = s.positions.at<cv::Vec2f>(y, x);
      const bool inside = p[0] >= 0 && p[0] <= w - 1 && p[1] >= 0 && p[1] <= h - 1;
      s.in_view.at<float>(y, x) =
          turned[static_cast<size_t>(y) * w + x].z() > 1e-6 && depth_ahead.at<float>(y, x) > 0 && inside ? 1.f : 0.f;
    }
  return s;
}

cv::Mat depthInCamera(const cv::Mat& anchor_depth, const cv::Mat& coords, const CameraPose& anchor_pose,
                      const CameraPose& pose, const CameraIntrinsics& camera) {
  CV_Assert(anchor_depth.type() == CV_32F && coords.type() == CV_32FC2);
  const RelativeTransform a_to_c = relativeTransform(pose, anchor_pose);
  const Eigen::RowVector3d z_row = a_to_c.rotation.row(2);
  const cv::Mat sampled = sampleBilinear(anchor_depth, coords, false);
  cv::Mat out(coords.size(), CV_32F);
  for (int y = 0; y < coords.rows; ++y)
    for (int x = 0; x < coords.cols; ++x) {
      const cv::Vec2f c = coords.at<cv::Vec2f>(y, x);
      const double z = z_row.dot(ray(camera, c[0], c[1])) * sampled.at<float>(y, x) + a_to_c.translation.z();
      out.at<float>(y, x) = static_cast<float>(std::max(z, kMinDepthM));
    }
  return out;
}

}  // namespace valerant
