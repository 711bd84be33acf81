// Evaluation metrics used on the visual SLAM: a known Sim(3) is recovered exactly,
// ATE and rotation error vanish for a transformed copy, a camera turning in place is
// handled without a Sim(3), and depth AbsRel is invariant to the depth scale.
#include <gtest/gtest.h>

#include <cmath>

#include "valerant/common/error.h"
#include "valerant/eval/trajectory_metrics.h"

using namespace valerant;

namespace {

Sim3 knownSim3() {
  Sim3 s;
  s.scale = 32.0 / 1.7;
  s.rotation = Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  s.translation = Eigen::Vector3d(100, -40, 25);
  return s;
}

std::vector<Eigen::Isometry3d> curve(int n) {
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i < n; ++i) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = Eigen::AngleAxisd(0.02 * i, Eigen::Vector3d::UnitY()).toRotationMatrix();
    p.translation() = Eigen::Vector3d(std::sin(0.1 * i), 0.05 * i, 0.2 * i);
    poses.push_back(p);
  }
  return poses;
}

std::vector<Eigen::Isometry3d> transformed(const std::vector<Eigen::Isometry3d>& poses, const Sim3& s) {
  std::vector<Eigen::Isometry3d> out;
  for (const auto& p : poses) {
    Eigen::Isometry3d q = Eigen::Isometry3d::Identity();
    q.linear() = s.rotation * p.linear();
    q.translation() = s.apply(p.translation());
    out.push_back(q);
  }
  return out;
}

}  // namespace

TEST(VisualMetrics, KnownSim3IsRecoveredExactly) {
  const Sim3 truth = knownSim3();
  std::vector<Eigen::Vector3d> est, gt;
  for (const auto& p : curve(20)) {
    est.push_back(p.translation());
    gt.push_back(truth.apply(p.translation()));
  }
  const Sim3 fit = alignSim3(est, gt);
  EXPECT_NEAR(fit.scale, truth.scale, 1e-9 * truth.scale);
  EXPECT_LT((fit.rotation - truth.rotation).norm(), 1e-9);
  EXPECT_LT((fit.translation - truth.translation).norm(), 1e-7);
}

TEST(VisualMetrics, AteOfTransformedCopyIsZeroAndNoiseShows) {
  const auto est = curve(30);
  auto gt = transformed(est, knownSim3());
  TrajectoryError e = trajectoryError(est, gt);
  EXPECT_TRUE(e.aligned);
  EXPECT_LT(e.ate_rmse, 1e-7);
  EXPECT_LT(e.rotation_rmse_deg, 1e-6);
  EXPECT_GT(e.path_length, 0);
  // Displace one truth centre by 1 unit: the RMSE can only be below 1/sqrt(30) of it.
  gt[10].translation().x() += 1.0;
  e = trajectoryError(est, gt);
  EXPECT_GT(e.ate_rmse, 0.05);
  EXPECT_LT(e.ate_rmse, 1.0 / std::sqrt(30.0) + 1e-9);
  EXPECT_NEAR(e.ate_percent, 100 * e.ate_rmse / e.path_length, 1e-12);
}

TEST(VisualMetrics, APathAlongALineTakesItsRollFromTheOrientations) {
  // Walking a corridor forth and back: every centre on the z axis (off it by 1e-4 in x
  // and y, alternating), the camera turning about y on the way. Positions fix neither
  // the roll about the line nor, through the noise, anything else; the cameras'
  // orientation does.
  std::vector<Eigen::Isometry3d> line;
  for (int i = 0; i < 40; ++i) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = Eigen::AngleAxisd(0.08 * i, Eigen::Vector3d::UnitY()).toRotationMatrix();
    p.translation() = Eigen::Vector3d(0, 0, i < 20 ? 0.3 * i : 0.3 * (39 - i));
    line.push_back(p);
  }
  const Sim3 s = knownSim3();
  const auto truth = transformed(line, s);
  auto estimate = line;
  for (int i = 0; i < 40; ++i) estimate[i].translation() += Eigen::Vector3d(i % 2 ? 1e-4 : -1e-4, i % 3 ? 1e-4 : -1e-4, 0);
  const auto by_orientation = alignSim3ByOrientation(estimate, truth);
  ASSERT_TRUE(by_orientation);
  EXPECT_LT(Eigen::AngleAxisd(by_orientation->rotation.transpose() * s.rotation).angle(), 1e-9);
  EXPECT_NEAR(by_orientation->scale, s.scale, 1e-3 * s.scale);
  const TrajectoryError e = trajectoryError(estimate, truth);
  ASSERT_TRUE(e.aligned);
  EXPECT_LT(Eigen::AngleAxisd(e.alignment.rotation.transpose() * s.rotation).angle(), 1e-9);
  // The residual is the noise, scaled: at most sqrt(2) 1e-4 x 18.8.
  EXPECT_LT(e.ate_rmse, 1.5e-4 * s.scale);
  // The same path run backwards against its orientations has no positive scale.
  auto reversed = estimate;
  for (auto& p : reversed) p.translation() = -p.translation();
  EXPECT_FALSE(alignSim3ByOrientation(reversed, truth));
}

TEST(VisualMetrics, TurningInPlaceNeedsNoSim3) {
  std::vector<Eigen::Isometry3d> est, gt;
  for (int i = 0; i < 10; ++i) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d::UnitY()).toRotationMatrix();
    est.push_back(p);
    Eigen::Isometry3d q = p;
    q.linear() = knownSim3().rotation * p.linear();
    q.translation() = Eigen::Vector3d(5, 6, 7);
    gt.push_back(q);
  }
  const TrajectoryError e = trajectoryError(est, gt);
  EXPECT_FALSE(e.aligned);
  EXPECT_LT(e.ate_rmse, 1e-12);
  EXPECT_TRUE(std::isnan(e.ate_percent));
  EXPECT_LT(e.rotation_rmse_deg, 1e-6);
}

TEST(VisualMetrics, BadInputNamesTheProblem) {
  EXPECT_THROW(alignSim3({Eigen::Vector3d::Zero()}, {}), InputError);
  EXPECT_THROW(trajectoryError({}, {}), InputError);
  const std::vector<Eigen::Vector3d> same(5, Eigen::Vector3d::Ones());
  EXPECT_THROW(alignSim3(same, same), InputError);
}

// Truth: three level cameras looking along x (optical z along world x, y down). The
// estimate: frame 0 the same; frame 1 pitched 3 deg (about its own x); frame 2 turned
// 10 deg in heading (about world z) and rolled 4 deg (about its own z, the optical axis).
// Rotated into the truth frame by the identity, the tilts are 0, 3 and 4 deg: heading does
// not count. An alignment that turns the estimate 30 deg about world z changes none;
// one that tips it 2 deg about world y adds 2 deg to the level frame 0.
TEST(VisualMetrics, TiltErrorIsRollAndPitchBlindToHeading) {
  Eigen::Matrix3d level;
  level.col(0) = Eigen::Vector3d(0, -1, 0);  // optical x: world -y
  level.col(1) = Eigen::Vector3d(0, 0, -1);  // optical y: world down
  level.col(2) = Eigen::Vector3d(1, 0, 0);   // optical z: world x
  const auto pose = [](const Eigen::Matrix3d& r) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = r;
    return p;
  };
  const auto deg = [](double d) { return d * M_PI / 180; };
  const std::vector<Eigen::Isometry3d> truth(3, pose(level));
  const std::vector<Eigen::Isometry3d> estimate = {
      pose(level), pose(level * Eigen::AngleAxisd(deg(3), Eigen::Vector3d::UnitX()).toRotationMatrix()),
      pose(Eigen::AngleAxisd(deg(10), Eigen::Vector3d::UnitZ()).toRotationMatrix() * level *
           Eigen::AngleAxisd(deg(4), Eigen::Vector3d::UnitZ()).toRotationMatrix())};
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const auto tilts = tiltErrorsDeg(estimate, truth, Eigen::Matrix3d::Identity(), up);
  ASSERT_EQ(tilts.size(), 3u);
  EXPECT_NEAR(tilts[0], 0, 1e-9);
  EXPECT_NEAR(tilts[1], 3, 1e-9);
  EXPECT_NEAR(tilts[2], 4, 1e-9);
  const auto turned = tiltErrorsDeg(estimate, truth, Eigen::AngleAxisd(deg(30), up).toRotationMatrix(), up);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(turned[i], tilts[i], 1e-9);
  const auto tipped =
      tiltErrorsDeg(estimate, truth, Eigen::AngleAxisd(deg(2), Eigen::Vector3d::UnitY()).toRotationMatrix(), up);
  EXPECT_NEAR(tipped[0], 2, 1e-9);
  EXPECT_THROW(tiltErrorsDeg(estimate, {truth[0]}, Eigen::Matrix3d::Identity(), up), InputError);
}

TEST(VisualMetrics, DepthAbsRelIsScaleInvariant) {
  cv::Mat truth(4, 4, CV_32F, cv::Scalar(2.0f)), est, conf(4, 4, CV_32F, cv::Scalar(5.0f));
  truth.at<float>(0, 0) = std::nanf("");
  est = truth / 8.0;                 // right up to scale 8 ...
  est.at<float>(1, 1) = 2.0f / 4.0f;  // ... except one pixel, 2x too far
  conf.at<float>(2, 2) = 1.0f;        // and one unconfident pixel
  const DepthError e = depthError({est}, {conf}, {truth}, 4.0);
  EXPECT_EQ(e.truth_pixels, 15);
  EXPECT_EQ(e.confident_pixels, 14);
  EXPECT_NEAR(e.scale, 8.0, 1e-6);
  EXPECT_NEAR(e.abs_rel, 1.0 / 14.0, 1e-6);
  EXPECT_NEAR(e.confident_fraction, 14.0 / 15.0, 1e-12);
  const DepthError none = depthError({cv::Mat()}, {cv::Mat()}, {truth}, 4.0);
  EXPECT_TRUE(std::isnan(none.abs_rel));
  EXPECT_EQ(none.confident_fraction, 0);
}
