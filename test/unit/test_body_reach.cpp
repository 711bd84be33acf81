// Where eq. 6's body cylinders can reach (body_reach.h), on hand-worked cases. The
// reference sample A stands on the floor z = 0 at (0, 0, 1), n0 = z, kappa 1; points lie
// in the slab 0 <= z <= 2. Boxes are tested through contains() on points, so the test
// does not depend on which way e1 and e2 point across n0.
#include <gtest/gtest.h>

#include <cmath>

#include "valerant/explore/body_reach.h"
#include "body_sample.h"

using namespace valerant;
using valerant::test::sampleAt;

namespace {

bool inside(const BodyReach& reach, const PlaneBox& box, const Eigen::Vector3d& p) {
  return box.contains(reach.across1(p), reach.across2(p));
}

const FloorPlane kA = sampleAt({0, 0, 1}, Eigen::Vector3d::UnitZ(), 1);
// B: at (5, 0, 1), its axis tilted 36.87 degrees towards +x (n = (0.6, 0, 0.8)), kappa 1.
const FloorPlane kB = sampleAt({5, 0, 1}, {0.6, 0, 0.8}, 1);

}  // namespace

// A vertical axis reaches a square of half-width r = 0.3 around it, whatever the slab.
TEST(BodyReach, AnUprightAxisReachesItsDisc) {
  const BodyReach reach(kA);
  const auto box = reach.span(kA, 0.3, 0, 2);
  ASSERT_TRUE(box.has_value());
  EXPECT_TRUE(inside(reach, *box, {0.299, -0.299, 7}));  // the height across n0 does not matter
  EXPECT_FALSE(inside(reach, *box, {0.301, 0, 1}));
  EXPECT_FALSE(inside(reach, *box, {0, -0.301, 1}));
}

// B's axis crosses the slab, widened by r, between t = (0 - 1 - 0.3) / 0.8 = -1.625 and
// t = (2 - 1 + 0.3) / 0.8 = 1.625, so along x it reaches 5 -+ 1.625 * 0.6 -+ 0.3: 3.725 to
// 6.275; across (y) the tilt adds nothing: -0.3 to 0.3.
TEST(BodyReach, ATiltedAxisReachesAlongItsTiltAcrossTheSlab) {
  const BodyReach reach(kA);
  const auto box = reach.span(kB, 0.3, 0, 2);
  ASSERT_TRUE(box.has_value());
  EXPECT_TRUE(inside(reach, *box, {6.274, 0, 0}));
  EXPECT_FALSE(inside(reach, *box, {6.276, 0, 0}));
  EXPECT_TRUE(inside(reach, *box, {3.726, 0.299, 0}));
  EXPECT_FALSE(inside(reach, *box, {3.724, 0, 0}));
  EXPECT_FALSE(inside(reach, *box, {5, 0.301, 0}));
  // The farthest point B really counts at the slab's top: c + t n + 0.3 (0.8, 0, -0.6)
  // with z = 1 + 0.8 t - 0.18 = 2, t = 1.475: x = 5 + 0.885 + 0.24 = 6.125, inside.
  EXPECT_TRUE(inside(reach, *box, {6.125, 0, 2}));
}

// Both samples: the bounding box of their spans, x -0.3 to 6.275 and y -0.3 to 0.3; a
// sample without a floor (kappa <= 0) reaches nothing and is passed over.
TEST(BodyReach, EverySampleTogetherIsTheirBoundingBox) {
  const BodyReach reach(kA);
  FloorPlane no_floor = sampleAt({50, 50, 1}, Eigen::Vector3d::UnitZ(), 1);
  no_floor.q = no_floor.c;  // kappa 0
  const auto box = reach.spanOfAll({kA, no_floor, kB}, 0.3, 0, 2);
  ASSERT_TRUE(box.has_value());
  EXPECT_TRUE(inside(reach, *box, {3, 0, 0}));  // between the two, in neither's span
  EXPECT_TRUE(inside(reach, *box, {-0.299, 0.299, 0}));
  EXPECT_FALSE(inside(reach, *box, {-0.301, 0, 0}));
  EXPECT_FALSE(inside(reach, *box, {50, 50, 0}));
}

// An axis tilted more than 60 degrees from n0 is no bounded box, so neither is the whole;
// no sample with a floor at all is no bound either (nothing is dropped on its account).
TEST(BodyReach, ASampleTiltedOver60DegreesBoundsNothing) {
  const BodyReach reach(kA);
  const FloorPlane tilted = sampleAt({0, 0, 1}, {std::sin(1.06), 0, std::cos(1.06)}, 1);  // 60.7 degrees
  EXPECT_FALSE(reach.span(tilted, 0.3, 0, 2).has_value());
  EXPECT_FALSE(reach.spanOfAll({kA, tilted}, 0.3, 0, 2).has_value());
  FloorPlane no_floor = kA;
  no_floor.q = no_floor.c;
  EXPECT_FALSE(reach.spanOfAll({no_floor}, 0.3, 0, 2).has_value());
}

TEST(BodyReach, TheReferenceIsTheFirstSampleWithAFloor) {
  FloorPlane no_floor = kB;
  no_floor.q = no_floor.c;
  FloorPlane not_finite = kB;
  not_finite.c.x() = std::nan("");
  const std::vector<FloorPlane> samples = {no_floor, not_finite, kA, kB};
  EXPECT_EQ(referenceSample(samples), &samples[2]);
  EXPECT_EQ(referenceSample({no_floor}), nullptr);
}
