#include "valerant/common/tum_trajectory.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "valerant/common/error.h"
#include "valerant/common/output_file.h"

namespace valerant {

void writeTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses) {
  std::ostringstream out;
  out << "# timestamp tx ty tz qx qy qz qw\n" << std::setprecision(9);
  for (const auto& p : poses) {
    const Eigen::Quaterniond q(p.pose.linear());
    const Eigen::Vector3d t = p.pose.translation();
    out << p.stamp << ' ' << t.x() << ' ' << t.y() << ' ' << t.z() << ' ' << q.x() << ' ' << q.y()
        << ' ' << q.z() << ' ' << q.w() << '\n';
  }
  writeFileAtomically(path, out.str());
}

void writeTumTrajectory(const std::string& path, const std::vector<Eigen::Isometry3d>& poses) {
  std::vector<StampedPose> stamped;
  stamped.reserve(poses.size());
  for (size_t i = 0; i < poses.size(); ++i) stamped.push_back({static_cast<double>(i), poses[i]});
  writeTumTrajectory(path, stamped);
}

std::vector<StampedPose> readTumTrajectory(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot read trajectory");
  std::vector<StampedPose> poses;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double v[8];
    for (double& x : v) {
      if (!(fields >> x) || !std::isfinite(x))
        throw InputError(path + ":" + std::to_string(number), "expected 8 finite numbers");
    }
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1.0) > 1e-3)
      throw InputError(path + ":" + std::to_string(number), "quaternion is not unit length");
    StampedPose p;
    p.stamp = v[0];
    p.pose.linear() = q.normalized().toRotationMatrix();
    p.pose.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    poses.push_back(p);
  }
  return poses;
}

}  // namespace valerant
