// The grid index behind eq. 6's counts (body_point_index.h) returns exactly the
// brute-force counts: on a hand-worked case, and on random clouds with tilted axes,
// far samples, a runaway-scale outlier and samples without a floor.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "valerant/explore/body_point_index.h"
#include "body_sample.h"

using namespace valerant;
using valerant::test::sampleAt;

namespace {

int bruteForce(const std::vector<Eigen::Vector3d>& points, const FloorPlane& s, double radius) {
  const double kappa = s.cameraHeight();
  if (!(kappa > 0)) return 0;
  int count = 0;
  for (const auto& p : points) count += s.axisDistanceSquared(p) <= (radius * kappa) * (radius * kappa);
  return count;
}

}  // namespace

TEST(BodyPointIndex, HandWorkedCounts) {
  // Vertical axis through (0, 0), kappa 1, rho 0.5: within 0.5 of the axis are
  // (0.3, 0, 0.5), (0, 0.49, 1.2) and (0.5, 0, 0.4) (exactly on the boundary, counted);
  // (0.6, 0, 0.5) and (0.4, 0.4, 0.2) (0.566 away) are outside: 3.
  const std::vector<Eigen::Vector3d> points = {{0.3, 0, 0.5}, {0, 0.49, 1.2}, {0.5, 0, 0.4}, {0.6, 0, 0.5},
                                               {0.4, 0.4, 0.2}};
  const FloorPlane s = sampleAt({0, 0, 1}, Eigen::Vector3d::UnitZ(), 1);
  const BodyPointIndex index(points, {s}, 0.5);
  EXPECT_EQ(index.count(s, 0.5), 3);
  // Moved to x = 0.55: (0.6, 0, 0.5) and (0.5, 0, 0.4) are 0.05 away, (0.3, 0, 0.5) 0.25
  // and (0.4, 0.4, 0.2) sqrt(0.15^2 + 0.4^2) = 0.427: 4.
  EXPECT_EQ(index.count(sampleAt({0.55, 0, 1}, Eigen::Vector3d::UnitZ(), 1), 0.5), 4);
  // No floor (kappa <= 0): 0.
  EXPECT_EQ(index.count(sampleAt({0, 0, 1}, Eigen::Vector3d::UnitZ(), -1), 0.5), 0);
}

TEST(BodyPointIndex, EqualsBruteForceOnRandomClouds) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const double scale = trial % 2 ? 0.05 : 3.0;  // a scaled SLAM map and a metric one
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i < 4000; ++i)
      points.push_back(scale * Eigen::Vector3d(8 * uniform(rng), 8 * uniform(rng), 1.5 * uniform(rng) + 0.75));
    if (trial % 3 == 0) points.push_back(scale * Eigen::Vector3d(3000, -2000, 40));  // runaway point
    const Eigen::Vector3d up = Eigen::Vector3d(0.1 * uniform(rng), 0.1 * uniform(rng), 1).normalized();
    std::vector<FloorPlane> samples;
    for (int i = 0; i < 40; ++i) {
      // Axes tilted up to ~25 deg from `up`, now and then 70 deg (brute force path),
      // some far outside the cloud, one without a floor.
      const double tilt = i % 13 == 5 ? 3.0 : 0.45;
      const Eigen::Vector3d n = (up + tilt * Eigen::Vector3d(uniform(rng), uniform(rng), 0)).normalized();
      const double reach = i % 7 == 3 ? 500 : 8;
      const Eigen::Vector3d c = scale * Eigen::Vector3d(reach * uniform(rng), reach * uniform(rng), 1);
      samples.push_back(sampleAt(c, n, i == 11 ? -scale : scale));
    }
    for (const double radius : {0.3, 0.42, 1.5}) {
      const BodyPointIndex index(points, samples, radius);
      for (size_t i = 0; i < samples.size(); ++i)
        ASSERT_EQ(index.count(samples[i], radius), bruteForce(points, samples[i], radius))
            << "trial " << trial << " radius " << radius << " sample " << i;
    }
  }
}

TEST(BodyPointIndex, BoundedByTheLargestRadiusItKeepsEveryCountOfItsSamples) {
  // The random clouds of the test above, with a map-sized spread of points (the committed
  // steps' points) around a short path: indexed for radii up to 1.5, the counts of the
  // index's own samples at 0.3, 0.42 and 1.5 equal the brute-force ones, whether it
  // drops far points or, where a sample is tilted past 60 deg, keeps them all.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const double scale = trial % 2 ? 0.05 : 3.0;
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i < 4000; ++i)
      points.push_back(scale * Eigen::Vector3d(40 * uniform(rng), 40 * uniform(rng), 1.5 * uniform(rng) + 0.75));
    if (trial % 3 == 0) points.push_back(scale * Eigen::Vector3d(3000, -2000, 40));
    const Eigen::Vector3d up = Eigen::Vector3d(0.1 * uniform(rng), 0.1 * uniform(rng), 1).normalized();
    std::vector<FloorPlane> samples;
    for (int i = 0; i < 40; ++i) {
      const double tilt = trial % 4 == 1 && i == 20 ? 3.0 : 0.45;
      const Eigen::Vector3d n = (up + tilt * Eigen::Vector3d(uniform(rng), uniform(rng), 0)).normalized();
      const Eigen::Vector3d c = scale * Eigen::Vector3d(0.1 * i + 0.3 * uniform(rng), 0.3 * uniform(rng), 1);
      samples.push_back(sampleAt(c, n, i == 11 ? -scale : scale));
    }
    const BodyPointIndex index(points, samples, 0.3, 1.5);
    for (const double radius : {0.3, 0.42, 1.5})
      for (size_t i = 0; i < samples.size(); ++i)
        ASSERT_EQ(index.count(samples[i], radius), bruteForce(points, samples[i], radius))
            << "trial " << trial << " radius " << radius << " sample " << i;
  }
}

TEST(BodyPointIndex, ARadiusOverTheBoundIsAnError) {
  const std::vector<Eigen::Vector3d> points = {{0.3, 0, 0.5}, {5, 0, 0.5}};
  const FloorPlane s = sampleAt({0, 0, 1}, Eigen::Vector3d::UnitZ(), 1);
  const BodyPointIndex index(points, {s}, 0.5, 1.0);
  // (5, 0, 0.5) is 5 from the only axis: dropped; (0.3, 0, 0.5) counts at 0.5 and 1.0.
  EXPECT_EQ(index.count(s, 0.5), 1);
  EXPECT_EQ(index.count(s, 1.0), 1);
  EXPECT_THROW(index.count(s, 1.01), std::invalid_argument);
  EXPECT_THROW(BodyPointIndex(points, {s}, 0.5, 0.4), std::invalid_argument);
}
