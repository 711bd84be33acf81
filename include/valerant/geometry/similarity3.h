#pragma once
// A similarity transform x -> s R x + t: what a monocular map is known up to, so what a
// loop closure corrects (a SLAM frame to the corrected map frame) and what the keyframe
// pose graph estimates per keyframe (camera to map, with the keyframe's own scale).
#include <Eigen/Geometry>
#include <algorithm>

namespace valerant {

struct Similarity3 {
  double scale = 1;
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  static Similarity3 fromIsometry(const Eigen::Isometry3d& pose, double scale = 1) {
    return Similarity3{scale, Eigen::Quaterniond(pose.linear()).normalized(), pose.translation()};
  }

  Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return scale * (rotation * p) + translation; }
  // (this o other)(x) = this(other(x)).
  Similarity3 operator*(const Similarity3& other) const {
    return Similarity3{scale * other.scale, (rotation * other.rotation).normalized(), apply(other.translation)};
  }
  Similarity3 inverse() const {
    const Eigen::Quaterniond r = rotation.conjugate();
    return Similarity3{1 / scale, r, -(r * translation) / scale};
  }
  // The rotation and translation alone (a camera pose once its scale is factored out).
  Eigen::Isometry3d isometry() const {
    Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
    out.linear() = rotation.toRotationMatrix();
    out.translation() = translation;
    return out;
  }
  // The farthest a point of `box` moves under this transform: x -> (sR - I)x + t is
  // affine, so the length of the move is convex and peaks at one of the box's corners.
  double maxDisplacement(const Eigen::AlignedBox3d& box) const {
    double farthest = 0;
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d corner = box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c));
      farthest = std::max(farthest, (apply(corner) - corner).norm());
    }
    return farthest;
  }
  // A camera pose (camera_to_frame) moved by this transform: rotated, its centre mapped.
  Eigen::Isometry3d applyTo(const Eigen::Isometry3d& camera_to_frame) const {
    Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
    out.linear() = rotation.toRotationMatrix() * camera_to_frame.linear();
    out.translation() = apply(camera_to_frame.translation());
    return out;
  }
};

}  // namespace valerant
