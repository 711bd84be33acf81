// Yaw and heading errors at the end of a recovered path (eval/end_of_path_error.h),
// worked by hand. World: z up; camera: optical frame (x right, y down, z forward).
#include <gtest/gtest.h>

#include <cmath>

#include "valerant/common/error.h"
#include "valerant/eval/end_of_path_error.h"

using namespace valerant;

namespace {

double radians(double deg) { return deg * M_PI / 180.0; }

// A level camera at `position` whose optical axis has yaw `yaw_deg` (0: along +x).
Eigen::Isometry3d levelCamera(double yaw_deg, const Eigen::Vector3d& position) {
  Eigen::Matrix3d facing_x;  // columns: optical x = -y, optical y = -z, optical z = +x
  facing_x << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(radians(yaw_deg), Eigen::Vector3d::UnitZ()).toRotationMatrix() * facing_x;
  pose.translation() = position;
  return pose;
}

}  // namespace

TEST(EndOfPathError, YawHeadingAndAngleBetween) {
  EXPECT_NEAR(cameraYawDeg(levelCamera(0, {1, 2, 3})), 0.0, 1e-12);
  EXPECT_NEAR(cameraYawDeg(levelCamera(90, {1, 2, 3})), 90.0, 1e-12);
  EXPECT_NEAR(cameraYawDeg(levelCamera(-135, {0, 0, 0})), -135.0, 1e-12);
  EXPECT_NEAR(headingDeg({0, 0, 0}, {1, 1, 5}), 45.0, 1e-12);  // height is ignored
  EXPECT_NEAR(headingDeg({2, 2, 0}, {2, 0, 0}), -90.0, 1e-12);
  EXPECT_NEAR(angleBetweenDeg(170, -170), 20.0, 1e-12);
  EXPECT_NEAR(angleBetweenDeg(10, 370), 0.0, 1e-12);
  EXPECT_NEAR(angleBetweenDeg(-90, 90), 180.0, 1e-12);
  EXPECT_NEAR(angleBetweenDeg(-100, 100), 160.0, 1e-12);
}

TEST(EndOfPathError, SlamPathInItsOwnFrame) {
  // Truth: from the origin facing +x, 10 units along +x (heading 0), ending turned to
  // yaw 90. The SLAM's map frame is its first camera's optical frame: it ends turned
  // 80 degrees left (about optical -y, i.e. R_y(-80 deg)) and moved (0.5, 0, 3) in
  // optical units: 3 forward (+x in the world) and 0.5 right (-y): heading
  // atan2(-0.5, 3) = -9.46232 degrees.
  const std::vector<Eigen::Isometry3d> truth = {levelCamera(0, {0, 0, 0}), levelCamera(90, {10, 0, 0})};
  Eigen::Isometry3d end = Eigen::Isometry3d::Identity();
  end.linear() = Eigen::AngleAxisd(radians(-80), Eigen::Vector3d::UnitY()).toRotationMatrix();
  end.translation() = Eigen::Vector3d(0.5, 0, 3);
  const std::vector<Eigen::Isometry3d> estimate = {Eigen::Isometry3d::Identity(), end};
  const EndOfPathError e = endOfPathError(estimate, truth, true);
  EXPECT_NEAR(e.yaw_error_deg, 10.0, 1e-9);
  ASSERT_TRUE(e.heading_error_deg.has_value());
  EXPECT_NEAR(*e.heading_error_deg, 9.46232, 1e-5);
  EXPECT_FALSE(endOfPathError(estimate, truth, false).heading_error_deg.has_value());  // turns in place
}

TEST(EndOfPathError, APerfectPathInAnotherFrameAndScaleHasNoError) {
  // estimate_i = M truth_i with translations scaled by s: aligned by the first pose,
  // the yaw and the direction of travel are exactly the truth's.
  std::vector<Eigen::Isometry3d> truth, estimate;
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  m.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, -1, 0.4).normalized()).toRotationMatrix();
  m.translation() = Eigen::Vector3d(3, -1, 2);
  for (int i = 0; i < 5; ++i) {
    truth.push_back(levelCamera(30 + 10 * i, {100 + 7.0 * i, -20 + 3.0 * i * i, 50}));
    Eigen::Isometry3d e = m * truth.back();
    e.translation() *= 0.01;
    estimate.push_back(e);
  }
  const EndOfPathError e = endOfPathError(estimate, truth, true);
  EXPECT_NEAR(e.yaw_error_deg, 0.0, 1e-9);
  EXPECT_NEAR(*e.heading_error_deg, 0.0, 1e-9);
}

TEST(EndOfPathError, AnEstimateThatDidNotMoveIsHalfATurnOff) {
  const std::vector<Eigen::Isometry3d> truth = {levelCamera(0, {0, 0, 0}), levelCamera(0, {10, 0, 0})};
  const std::vector<Eigen::Isometry3d> estimate(2, Eigen::Isometry3d::Identity());
  const EndOfPathError e = endOfPathError(estimate, truth, true);
  EXPECT_NEAR(e.yaw_error_deg, 0.0, 1e-12);
  EXPECT_EQ(*e.heading_error_deg, 180.0);
}

TEST(EndOfPathError, PathsOfDifferentLengthsAreAnError) {
  EXPECT_THROW(endOfPathError({Eigen::Isometry3d::Identity()}, {}, true), InputError);
  EXPECT_THROW(endOfPathError({}, {}, false), InputError);
}
