// Hand-worked eye heights of keyframes (map/eye_height_drift.h).
#include <gtest/gtest.h>

#include <cmath>

#include "valerant/map/eye_height_drift.h"

using namespace valerant;

namespace {
// A keyframe whose camera stands at `eye` (optical frame: y down, so up is -y), turned
// `yaw` about that up, with `floor` points `depth` under the camera at height h.
std::shared_ptr<const FusedKeyframe> keyframe(const Eigen::Vector3d& eye, double yaw, int floor, double depth,
                                              float h) {
  auto k = std::make_shared<FusedKeyframe>();
  k->camera_to_map.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
  k->camera_to_map.translation() = eye;
  for (int i = 0; i < floor; ++i) {
    FusedPoint p;
    p.position = (eye + Eigen::Vector3d(0.1 * i, depth, 1.0 + 0.05 * i)).cast<float>();  // y down: under the eye
    p.h = h;
    k->points.push_back(p);
  }
  return k;
}
}  // namespace

// A: 60 floor points 2 under the eye at h = 0: kappa 2. B: 60 points 0.96 under at
// h = 0.04, the floor 0.04 kappa under them: 0.96 / (1 - 0.04) = 1; its 100 wall points
// (h = 0.5) are no floor. C: 49 floor points, too few. D: turned 90 degrees about its
// up, 60 points 1.5 under at h = 0: 1.5. Against kappa_0 = 2 the ratios are 1, 0.5 and
// 0.75: min 0.5, max 1, the latest three's median 0.75.
TEST(EyeHeightDrift, EveryKeyframeMeasuresItsEyeOverItsOwnFloor) {
  auto b = std::const_pointer_cast<FusedKeyframe>(keyframe({10, 0, 0}, 0, 60, 0.96, 0.04f));
  for (int i = 0; i < 100; ++i) {
    FusedPoint wall;
    wall.position = Eigen::Vector3f(12, 0.5f * static_cast<float>(i % 3), 3);
    wall.h = 0.5f;
    b->points.push_back(wall);
  }
  const std::vector<std::shared_ptr<const FusedKeyframe>> keyframes = {
      keyframe({0, 0, 0}, 0, 60, 2.0, 0.0f), b, keyframe({20, 0, 0}, 0, 49, 1.0, 0.0f),
      keyframe({30, 0, 5}, M_PI / 2, 60, 1.5, 0.0f)};
  EXPECT_NEAR(*keyframeEyeHeight(*keyframes[0]), 2.0, 1e-6);
  EXPECT_NEAR(*keyframeEyeHeight(*keyframes[1]), 1.0, 1e-6);
  EXPECT_FALSE(keyframeEyeHeight(*keyframes[2]).has_value());
  EXPECT_NEAR(*keyframeEyeHeight(*keyframes[3]), 1.5, 1e-6);

  const EyeHeightDrift drift = eyeHeightDrift(keyframes, 2.0);
  EXPECT_EQ(drift.measured_keyframes, 3);
  EXPECT_NEAR(drift.min_ratio, 0.5, 1e-6);
  EXPECT_NEAR(drift.max_ratio, 1.0, 1e-6);
  EXPECT_NEAR(drift.last_ratio, 0.75, 1e-6);
}

// No anchor floor (kappa_0 unknown) or no keyframe with its floor in view: nothing measured.
TEST(EyeHeightDrift, NothingToMeasureGivesNoRatios) {
  const std::vector<std::shared_ptr<const FusedKeyframe>> keyframes = {keyframe({0, 0, 0}, 0, 60, 2.0, 0.0f)};
  EXPECT_EQ(eyeHeightDrift(keyframes, 0).measured_keyframes, 0);
  EXPECT_EQ(eyeHeightDrift({keyframe({0, 0, 0}, 0, 10, 2.0, 0.0f)}, 2.0).measured_keyframes, 0);
  EXPECT_EQ(eyeHeightDrift({}, 2.0).last_ratio, 0);
}
