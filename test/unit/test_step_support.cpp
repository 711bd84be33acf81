// The step-aware body cylinder of eq. 6 (step_support.h) against the paper's, on
// hand-built scenes: floor z = 0, camera 1 above it (kappa = 1, so h = z), the body
// walking along +X; heights in eye heights (Quake III: a stair of 16 units over the
// 50-unit eye is 0.32, the player's 18-unit step 0.36).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "level_walk.h"
#include "valerant/explore/point_cloud_collision.h"
#include "valerant/explore/step_support.h"

using namespace valerant;

namespace {

using test::floorUnder;
using test::track;

HeightedPoint at(double x, double y, double z) { return {{x, y, z}, z, 10}; }

CollisionConfig stepped() {
  CollisionConfig config;
  config.step_height = 0.36;
  return config;
}

// Five risers of 0.32 every 0.32 from x = 1 (16-unit treads every 16 units), then a
// landing at 1.6 to x = 3.52: riser k at x = 1 + 0.32 k, z = 0.32 k + 0.04 m (m = 0..8);
// its tread at z = 0.32 (k + 1) from 0.04 to 0.28 past it; y = 0.025 j, |y| <= 0.5.
std::vector<HeightedPoint> staircase() {
  std::vector<HeightedPoint> points;
  for (int k = 0; k < 5; ++k) {
    const double riser = 1 + 0.32 * k, tread = 0.32 * (k + 1);
    for (int j = -20; j <= 20; ++j) {
      const double y = 0.025 * j;
      for (int m = 0; m <= 8; ++m) points.push_back(at(riser, y, 0.32 * k + 0.04 * m));
      for (int n = 1; n <= (k < 4 ? 7 : 30); ++n) points.push_back(at(riser + 0.04 * n, y, tread));
    }
  }
  return points;
}

// A face across x = 3 from the floor to `top`, and its top surface to x = 4; spacing 0.05.
std::vector<HeightedPoint> ledge(double top) {
  std::vector<HeightedPoint> points;
  for (int j = -20; j <= 20; ++j) {
    const double y = 0.05 * j;
    for (int m = 0; 0.05 * m <= top + 1e-9; ++m) points.push_back(at(3, y, 0.05 * m));
    for (int n = 1; n <= 20; ++n) points.push_back(at(3 + 0.05 * n, y, top));
  }
  return points;
}

// The samples with each eye one above the floor under it (the engine lifts and drops
// the camera with the player), floor_z(x) that floor's height.
template <class FloorZ>
std::vector<FloorPlane> eyeOver(std::vector<FloorPlane> samples, FloorZ floor_z) {
  for (FloorPlane& s : samples) {
    s.q.z() = floor_z(s.c.x());
    s.c.z() = s.q.z() + 1;
  }
  return samples;
}

// The floor under the staircase(): 0 before the first riser, then the tread of the last
// riser passed (the landing's 1.6 from x = 2.28).
double staircaseFloor(double x) {
  if (x < 1) return 0;
  return 0.32 * (std::min(4.0, std::floor((x - 1) / 0.32)) + 1);
}

// Wall points on x = 3, |y| <= 1, z in [0, 2], spaced 0.1 (test_collision.cpp's sparse wall).
std::vector<HeightedPoint> sparseWall() {
  std::vector<HeightedPoint> points;
  for (int j = -10; j <= 10; ++j)
    for (int m = 0; m <= 20; ++m) points.push_back(at(3, 0.1 * j, 0.1 * m));
  return points;
}

}  // namespace

TEST(StepSupport, TheSteppedBodyClimbsAStaircaseThePaperCannot) {
  // sample i at x = 0.05 (i + 1), the eye over the tread it stands on
  const auto samples = eyeOver(track(0, 3, 60), staircaseFloor);
  // The paper: the disc first reaches the first riser at sample 15 (x = 0.8, 0.2 from
  // it: |y| <= 0.064, 5 columns x 4 rows at z 0.20..0.32 = 20); at sample 16 (x = 0.85:
  // |y| <= 0.147, 11 columns x 4 = 44, plus 7 points of the first tread at x = 1.04,
  // 0.19 away) 51; sample 17 is the second in a row at or above 30.
  const auto paper = detectPointCloudCollision(staircase(), samples, CollisionConfig(), false);
  EXPECT_TRUE(paper.collision);
  EXPECT_EQ(paper.sample, 17);
  EXPECT_EQ(paper.run_start, 16);
  // Stepped: each riser enters the disc alone and reaches at most 0.32 over the tread
  // before, so nothing is ever above the step and every count is 0. The support is 0
  // until sample 14 (x = 0.75, nothing within 0.21), the first tread (0.32) from sample
  // 15; at sample 29 (x = 1.5) the disc reaches the riser at 1.64 (0.96); at the end
  // the landing (1.6). The body leads the eye by one riser (0.32, within the step): at
  // sample 29 the eye is still over the second tread (0.64).
  const auto climb = detectPointCloudCollision(staircase(), samples, stepped(), false);
  EXPECT_FALSE(climb.collision);
  EXPECT_EQ(climb.occupied_max, 0);
  const SteppedCounts s = steppedBodyCounts(staircase(), samples, stepped(), stepped().body_radius);
  EXPECT_DOUBLE_EQ(s.support[14], 0.0);
  EXPECT_NEAR(s.support[15], 0.32, 1e-12);
  EXPECT_NEAR(s.support[29], 0.96, 1e-12);
  EXPECT_NEAR(s.support.back(), 1.6, 1e-12);
}

TEST(StepSupport, AWallTallerThanAStepCountsAsInThePaper) {
  // A face rising above the step enters the disc at all its heights at once: blocked
  // from the first sample that reaches it, the support stays on the floor and the
  // counts are the paper's (test_collision.cpp: 30 at sample 32, 50 at sample 33).
  const auto samples = track(0, 5, 57);
  const auto paper = detectPointCloudCollision(sparseWall(), samples, CollisionConfig(), false);
  const auto wall = detectPointCloudCollision(sparseWall(), samples, stepped(), false);
  EXPECT_TRUE(wall.collision);
  EXPECT_EQ(wall.sample, 33);
  EXPECT_EQ(wall.sample, paper.sample);
  EXPECT_EQ(wall.occupied_max, 50);
  const SteppedCounts s = steppedBodyCounts(sparseWall(), samples, stepped(), stepped().body_radius);
  EXPECT_EQ(s.counts[32], 30);
  EXPECT_EQ(s.counts[33], 50);
  for (const double f : s.support) EXPECT_DOUBLE_EQ(f, 0.0);
}

TEST(StepSupport, ALedgeAboveAStepCollidesOneWithinAStepIsClimbed) {
  const auto samples = track(0, 5, 57);  // sample i at x = 5 (i + 1) / 57
  // A 0.5 ledge (25 units, over Quake's 18): its face rises above 0.36, so it is counted
  // as the paper counts it. Sample 31 (x = 2.807, 0.193 from the face: |y| <= 0.083,
  // 3 columns x 7 rows at z 0.20..0.50) = 21; sample 32 (x = 2.895: |y| <= 0.182,
  // 7 columns x 7 = 49, plus 5 + 1 points of the top at x = 3.05 and 3.10) = 55;
  // sample 33 fires.
  const auto high = detectPointCloudCollision(ledge(0.5), samples, stepped(), false);
  EXPECT_TRUE(high.collision);
  EXPECT_EQ(high.sample, 33);
  EXPECT_EQ(high.run_start, 32);
  const SteppedCounts h = steppedBodyCounts(ledge(0.5), samples, stepped(), stepped().body_radius);
  EXPECT_EQ(h.counts[31], 21);
  EXPECT_EQ(h.counts[32], 55);
  // A 0.3 ledge (15 units): the paper counts 9, 27 (7 columns x 3 rows + 6 of the top),
  // 46 (9 columns x 3 + 7 + 7 + 5 of the top), ... and fires at sample 34; the stepped
  // body steps onto it at sample 31, where the disc first reaches it, and never counts.
  const auto paper = detectPointCloudCollision(ledge(0.3), samples, CollisionConfig(), false);
  EXPECT_TRUE(paper.collision);
  EXPECT_EQ(paper.sample, 34);
  const auto low = detectPointCloudCollision(ledge(0.3), samples, stepped(), false);
  EXPECT_FALSE(low.collision);
  EXPECT_EQ(low.occupied_max, 0);
  const SteppedCounts l = steppedBodyCounts(ledge(0.3), samples, stepped(), stepped().body_radius);
  EXPECT_DOUBLE_EQ(l.support[30], 0.0);
  EXPECT_NEAR(l.support[31], 0.3, 1e-12);
}

TEST(StepSupport, TheSupportFallsOffADropWithTheEyeAndIgnoresWhatIsAboveTheBody) {
  // A lower floor at -2 (a drop) from x = 1, and a ceiling at 1.5 over x 0..2: samples
  // at x = 0.4, 0.8, ..., 2.0, the eye falling to the lower floor once past the edge.
  // At x = 0.4 the disc holds only the ceiling, over f + eta_high: nothing counts, the
  // support stays 0. At x = 0.8 the lower floor's first row (x = 1, 0.2 away) is in the
  // disc, but the eye still stands on the upper floor: the body goes down one step
  // (-0.36). From x = 1.2 the eye is over the lower floor and the body stands on it.
  std::vector<HeightedPoint> points;
  for (int n = 0; n <= 40; ++n)
    for (int j = -4; j <= 4; ++j) {
      points.push_back(at(1 + 0.05 * n, 0.05 * j, -2));
      points.push_back(at(0.05 * n, 0.05 * j, 1.5));
    }
  const auto samples = eyeOver(track(0, 2, 5), [](double x) { return x < 1 ? 0.0 : -2.0; });
  const SteppedCounts s = steppedBodyCounts(points, samples, stepped(), stepped().body_radius);
  EXPECT_EQ(s.counts, (std::vector<int>{0, 0, 0, 0, 0}));
  EXPECT_DOUBLE_EQ(s.support[0], 0.0);
  EXPECT_DOUBLE_EQ(s.support[1], -0.36);
  EXPECT_DOUBLE_EQ(s.support[2], -2.0);
  EXPECT_DOUBLE_EQ(s.support.back(), -2.0);
}

TEST(StepSupport, TheBodyStaysWithinAStepOfALevelEye) {
  // A face that rises 0.1 every 0.05 along x from x = 1 (h = 0.1 m at x = 1 + 0.05 m,
  // m = 0..40; |y| <= 0.5 every 0.05): a wall as a floor fitted 19 degrees off shows
  // it (oa_dm3 spawn 1). The samples (x = 0.1 (i + 1)) advance 0.1, so the highest point
  // of each disc is 0.2 over the last one's, within the step: followed alone, the body
  // would climb it like a ramp and never count. The eye stays level (floor 0), so the
  // body stands at most 0.36 over it:
  //   x = 0.9 (i 8): the disc holds h 0, 0.1, 0.2: support 0.2;
  //   x = 1.0 (i 9): up to 0.4 (x = 1.2), within 0.2 + 0.36: support 0.36, the bound;
  //   x = 1.1 (i 10): up to 0.6, within 0.72: still 0.36, no count;
  //   x = 1.2 (i 11): 0.8 (x = 1.4) is over 0.72: blocked; the band 0.54..1.55 holds
  //     x = 1.3, 1.35, 1.4 at 0.1, 0.15, 0.2 from the axis: 7 + 5 + 3 = 15 points;
  //   x = 1.3 (i 12): x = 1.3 .. 1.5 at 0 .. 0.2: 9 + 9 + 7 + 5 + 3 = 33;
  //   x = 1.4 (i 13): x = 1.3 .. 1.6: 7 + 9 + 9 + 9 + 7 + 5 + 3 = 49, the second
  //     sample in a row at N_occ 30: a collision from sample 12.
  std::vector<HeightedPoint> points;
  for (int m = 0; m <= 40; ++m)
    for (int j = -10; j <= 10; ++j) points.push_back({{1 + 0.05 * m, 0.05 * j, 0.1 * m}, 0.1 * m, 10});
  const auto samples = track(0, 3, 30);
  const SteppedCounts s = steppedBodyCounts(points, samples, stepped(), stepped().body_radius);
  EXPECT_NEAR(s.support[8], 0.2, 1e-12);
  for (size_t i = 9; i < s.support.size(); ++i) EXPECT_NEAR(s.support[i], 0.36, 1e-12) << i;
  EXPECT_EQ(s.counts[10], 0);
  EXPECT_EQ(s.counts[11], 15);
  EXPECT_EQ(s.counts[12], 33);
  EXPECT_EQ(s.counts[13], 49);
  const auto pc = detectPointCloudCollision(points, samples, stepped(), false);
  EXPECT_TRUE(pc.collision);
  EXPECT_EQ(pc.sample, 13);
  EXPECT_EQ(pc.run_start, 12);
}

TEST(StepSupport, ALedgeTheEyeWasNotLiftedOntoCountsOverTheEyesFloor) {
  // The whole-level body (rho 0.30, s = 0.45) and a 0.42 ledge (21 units, over the
  // engine's 18-unit step, so the engine keeps the feet on the floor: the eye stays
  // level): its face x = 3, z 0..0.40 every 0.05 (9 rows), its top z = 0.42 from x = 3.05;
  // samples x_i = 5 (i + 1) / 57.
  CollisionConfig config;
  config.body_radius = 0.30;
  config.step_height = 0.45;
  const auto samples = track(0, 5, 57);
  // Without the lag the body climbs it: nothing rises over f + 0.45, so nothing counts.
  const SteppedCounts climbed = steppedBodyCounts(ledge(0.42), samples, config, config.body_radius);
  EXPECT_NEAR(climbed.support.back(), 0.42, 1e-12);
  EXPECT_FALSE(detectPointCloudCollision(ledge(0.42), samples, config, false).collision);
  // L = 3:
  //   i 30 (x 2.719, 0.281 from the face: |y| <= 0.106, 5 columns): f 0.40 (the face's
  //     top row), over e + eta_low = 0.18: u 1, count 0;
  //   i 31 (x 2.807): the top's first rows reach the disc: f 0.42, u 2; i 32: u 3;
  //   i 33 (x 2.982, 0.018 from the face): u 4 > 3, counted over e = 0: the face's rows
  //     0.20..0.40 (5) x 11 columns (|y| <= 0.2995) = 55, and the top at x 3.05, 3.10,
  //     3.15, 3.20, 3.25 (|y| <= 0.292, 0.276, 0.249, 0.207, 0.136) = 11 + 11 + 9 + 9 + 5
  //     = 45: 100;
  //   i 34 (x 3.070): the face 5 x 11 = 55, the top x 3.05 .. 3.35 = 11 + 11 + 11 + 11 +
  //     9 + 7 + 5 = 65: 120, the second in a row at N_occ: a collision from sample 33.
  config.climb_lag = 3;
  const SteppedCounts s = steppedBodyCounts(ledge(0.42), samples, config, config.body_radius);
  EXPECT_DOUBLE_EQ(s.support[29], 0.0);
  EXPECT_NEAR(s.support[30], 0.40, 1e-12);
  EXPECT_NEAR(s.support[31], 0.42, 1e-12);
  for (int i = 0; i <= 32; ++i) EXPECT_EQ(s.counts[i], 0) << i;
  EXPECT_EQ(s.counts[33], 100);
  EXPECT_EQ(s.counts[34], 120);
  const auto pc = detectPointCloudCollision(ledge(0.42), samples, config, false);
  EXPECT_TRUE(pc.collision);
  EXPECT_EQ(pc.sample, 34);
  EXPECT_EQ(pc.run_start, 33);
}

TEST(StepSupport, AClimbTheEyeFollowsIsNoCollision) {
  // The staircase again, the eye now lifted as the engine lifts it: onto the highest
  // tread under the body (here within 0.2 ahead of the axis, so at the sample where the
  // disc, of radius 0.21, reaches a riser or at the next). The body never stands over the
  // eye's floor for more than one sample, so with L = 3 it climbs exactly as without.
  const auto samples = eyeOver(track(0, 3, 60), [](double x) { return staircaseFloor(x + 0.2); });
  CollisionConfig config = stepped();
  const SteppedCounts free_climb = steppedBodyCounts(staircase(), samples, config, config.body_radius);
  config.climb_lag = 3;
  const SteppedCounts s = steppedBodyCounts(staircase(), samples, config, config.body_radius);
  EXPECT_EQ(s.support, free_climb.support);
  EXPECT_EQ(s.counts, std::vector<int>(samples.size(), 0));
  EXPECT_NEAR(s.support.back(), 1.6, 1e-12);
  EXPECT_FALSE(detectPointCloudCollision(staircase(), samples, config, false).collision);
}

TEST(StepSupport, TheEyesFloorIsItsHeightOverTheFirstFloorLessOne) {
  // The first sample's floor is the datum: z = 0 under an eye 2 above it (kappa 2). An
  // eye at z 3 stands on a floor 0.5 datum camera heights up; one at z 1, 0.5 down.
  FloorPlane first;
  first.q = {0, 0, 0};
  first.c = {0, 0, 2};
  FloorPlane up = first, down = first;
  up.c.z() = 3;
  down.c.z() = 1;
  const std::vector<double> e = eyeSupports({first, up, down});
  EXPECT_EQ(e, (std::vector<double>{0.0, 0.5, -0.5}));
  EXPECT_TRUE(eyeSupports({}).empty());
  EXPECT_DOUBLE_EQ(withinAStepOfTheEye(1.0, 0.5, 0.36), 0.86);
  EXPECT_DOUBLE_EQ(withinAStepOfTheEye(-1.0, 0.5, 0.36), 0.14);
  EXPECT_DOUBLE_EQ(withinAStepOfTheEye(0.6, 0.5, 0.36), 0.6);
  EXPECT_DOUBLE_EQ(withinAStepOfTheEye(0.6, std::nan(""), 0.36), 0.6);
}

// [ours] step_count above_step: floor read a little high within a step, with one stray
// point over the step, is no wall. Samples at x = 0.25, 0.5, 0.75, 1 (rho 0.21, step
// 0.45); 40 floor points at z 0.30 on x = 0.5 and 40 at z 0.25 on x = 0.75 (|y| <= 0.1:
// each group inside one sample's disc only, the other 0.25 away), and one point at z 0.60
// on each line. The band (eta_low 0.18 up): sample 0 holds nothing (the support stays 0);
// at samples 1 and 2 the point at 0.60 is over the step (0 + 0.45), so the disc is blocked,
// the support stays 0 and the band counts 40 + 1 = 41 twice in a row: a collision. Over
// the step only: 1 and 1, no collision. A face of 40 points at z 0.60 in place of each
// stray point counts 40 at both samples (the floor below it not), and collides in both.
TEST(StepSupport, FloorWithinAStepIsNoWallWhenOnlyWhatRisesOverTheStepCounts) {
  const auto samples = track(0, 1, 4);
  CollisionConfig band;
  band.step_height = 0.45;
  CollisionConfig over = band;
  over.step_count = "above_step";
  std::vector<HeightedPoint> scatter;
  for (int j = -20; j < 20; ++j) {
    scatter.push_back(at(0.5, 0.005 * j, 0.30));
    scatter.push_back(at(0.75, 0.005 * j, 0.25));
  }
  std::vector<HeightedPoint> stray = scatter, face = scatter;
  stray.push_back(at(0.5, 0, 0.60));
  stray.push_back(at(0.75, 0, 0.60));
  for (int j = -20; j < 20; ++j) {
    face.push_back(at(0.5, 0.005 * j, 0.60));
    face.push_back(at(0.75, 0.005 * j, 0.60));
  }
  const SteppedCounts banded = steppedBodyCounts(stray, samples, band, band.body_radius);
  EXPECT_EQ(banded.counts, (std::vector<int>{0, 41, 41, 0}));
  EXPECT_EQ(banded.support, (std::vector<double>{0, 0, 0, 0}));
  EXPECT_TRUE(detectPointCloudCollision(stray, samples, band, false).collision);
  EXPECT_EQ(steppedBodyCounts(stray, samples, over, over.body_radius).counts, (std::vector<int>{0, 1, 1, 0}));
  EXPECT_FALSE(detectPointCloudCollision(stray, samples, over, false).collision);
  EXPECT_EQ(steppedBodyCounts(face, samples, over, over.body_radius).counts, (std::vector<int>{0, 40, 40, 0}));
  EXPECT_EQ(steppedBodyCounts(face, samples, band, band.body_radius).counts, (std::vector<int>{0, 80, 80, 0}));
  EXPECT_TRUE(detectPointCloudCollision(face, samples, over, false).collision);
}

TEST(StepSupport, ThePaperSettingKeepsThePapersCounts) {
  // step_height 0: bodyCylinderCounts is eq. 6 itself (the staircase's first riser
  // counts 20 at sample 15).
  const auto counts = bodyCylinderCounts(staircase(), track(0, 3, 60), CollisionConfig(), {0.21}).front();
  EXPECT_EQ(counts[15], 20);
  EXPECT_EQ(counts[16], 51);
}

namespace {

// The rule of step_support.h over every point, as the definition reads: the reference
// the indexed counts must equal.
SteppedCounts steppedByBruteForce(const std::vector<HeightedPoint>& points, const std::vector<FloorPlane>& samples,
                                  const CollisionConfig& config, double radius) {
  SteppedCounts out;
  double support = 0;
  int unfollowed = 0;
  for (const FloorPlane& s : samples) {
    const double eye = samples.front().normalisedHeight(s.c) - 1;
    auto withinAStep = [&](double f) {
      return std::min(std::max(f, eye - config.step_height), eye + config.step_height);
    };
    support = withinAStep(support);
    const double kappa = s.cameraHeight();
    bool blocked = false, any_tread = false;
    int band = 0, over_step = 0, eye_band = 0;
    double tread = support;
    for (const auto& p : points) {
      if (!(kappa > 0) || p.confidence < config.min_confidence || !p.position.allFinite()) continue;
      if (s.axisDistanceSquared(p.position) > radius * radius * kappa * kappa) continue;
      if (p.h >= eye + config.height_low && p.h <= eye + config.height_high) ++eye_band;
      if (p.h > support + config.height_high) continue;
      if (p.h > support + config.step_height) {
        blocked = true;
        ++over_step;
      }
      if (p.h >= support + config.height_low) ++band;
      if (p.h <= support + config.step_height) {
        tread = any_tread ? std::max(tread, p.h) : p.h;
        any_tread = true;
      }
    }
    if (!blocked) support = withinAStep(tread);
    unfollowed = support > eye + config.height_low ? unfollowed + 1 : 0;
    const bool not_climbed = config.climb_lag > 0 && unfollowed > config.climb_lag;
    const int blocked_count = config.step_count == "above_step" ? over_step : band;
    out.counts.push_back(not_climbed ? eye_band : blocked ? blocked_count : 0);
    out.support.push_back(support);
  }
  return out;
}

}  // namespace

// The counts and supports from the index equal the definition's on random terraces
// (heights in steps of 0.1 up to 2, some points unconfident, one non-finite), walked by
// tilted axes whose eyes rise and fall (the bound by the eye bites), at two radii from
// one index, as the branch check asks for rho and the prefix clearance; half the trials
// with the climb lag (L = 2), which the rising terraces and wandering eyes set off, and
// trials 4 to 7 counting only what rises over the step (step_count above_step).
TEST(StepSupport, IndexedCountsEqualTheDefinition) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(-1, 1);
  int lag_changed = 0;  // lagged trials whose counts differ from the same walk without the lag
  for (int trial = 0; trial < 10; ++trial) {
    CollisionConfig config = stepped();
    config.climb_lag = trial % 2 ? 2 : 0;
    if (trial >= 4 && trial < 8) config.step_count = "above_step";
    std::vector<HeightedPoint> points;
    for (int i = 0; i < 3000; ++i) {
      const double x = 4 * uniform(rng), y = 2 * uniform(rng);
      const double z = 0.1 * std::floor(10 * std::max(0.0, x + 0.5 * uniform(rng)) / 2);  // terraces rising along x
      points.push_back({{x, y, z}, z, i % 17 == 0 ? 1.0f : 10.0f});
    }
    points.push_back({{std::nan(""), 0, 0}, 0, 10});
    std::vector<FloorPlane> samples = track(-4, 4, 50);
    for (FloorPlane& s : samples) {  // tilt each axis a little, as fitted floors are; eyes up and down
      s.n = Eigen::Vector3d(0.05 * uniform(rng), 0.05 * uniform(rng), 1).normalized();
      s.c.z() += 0.5 * uniform(rng);
      s.q = s.c - s.n;
    }
    const std::vector<double> radii = {0.3, 0.5};
    const std::vector<SteppedCounts> indexed = steppedBodyCounts(points, samples, config, radii);
    for (size_t r = 0; r < radii.size(); ++r) {
      const SteppedCounts expected = steppedByBruteForce(points, samples, config, radii[r]);
      EXPECT_EQ(indexed[r].counts, expected.counts) << "trial " << trial << " radius " << radii[r];
      EXPECT_EQ(indexed[r].support, expected.support) << "trial " << trial << " radius " << radii[r];
    }
    CollisionConfig unlagged = config;
    unlagged.climb_lag = 0;
    if (config.climb_lag > 0 && indexed[0].counts != steppedBodyCounts(points, samples, unlagged, radii[0]).counts)
      ++lag_changed;
  }
  EXPECT_GT(lag_changed, 0);
}
