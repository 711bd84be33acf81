#pragma once
// TUM RGB-D trajectory format: one line per pose, "stamp x y z qx qy qz qw".
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace valerant {

struct StampedPose {
  double stamp = 0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

// Writes all poses; throws InputError naming the file when it cannot be written.
void writeTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses);
// The same, each pose stamped with its index (a run's frames and keyframes have no time).
void writeTumTrajectory(const std::string& path, const std::vector<Eigen::Isometry3d>& poses);
// Reads a TUM file ('#' comments allowed); throws InputError naming file and line.
std::vector<StampedPose> readTumTrajectory(const std::string& path);

}  // namespace valerant
