// RewoundHeadings (rewound_headings.h) on hand-worked walks over a flat grid whose floor
// is z = 0 and whose u axis is +X, so a walk's heading is atan2(y, x); tolerance 11.25
// degrees (a quarter of jw / lw's 45-degree turn).
#include <gtest/gtest.h>

#include <cmath>

#include "unit_grid.h"
#include "valerant/explore/rewound_headings.h"

using namespace valerant;

namespace {

using test::unitGrid;

Eigen::Vector3d walkAt(double deg, double length = 2.0) {
  const double a = deg * M_PI / 180.0;
  return {length * std::cos(a), length * std::sin(a), 0};
}

}  // namespace

TEST(RewoundHeadings, BarsOnlyHeadingsWithinTheToleranceFromTheSameState) {
  const CoverageGrid grid = unitGrid();
  RewoundHeadings rewound(11.25);
  rewound.rewoundTo(3, walkAt(0));                         // along +X from the state after 3 steps
  EXPECT_TRUE(rewound.barred(3, walkAt(10, 8.0), grid));   // 10 degrees off, longer: the same way
  EXPECT_TRUE(rewound.barred(3, walkAt(-10, 0.5), grid));
  EXPECT_FALSE(rewound.barred(3, walkAt(12), grid));       // 12 degrees: a way of its own
  EXPECT_FALSE(rewound.barred(3, walkAt(180), grid));      // straight back
  EXPECT_TRUE(rewound.barred(3, {2, 0, 5}, grid));         // climbing: heading 0 on the floor
  EXPECT_FALSE(rewound.barred(4, walkAt(0), grid));        // another state
  EXPECT_FALSE(rewound.barred(2, walkAt(0), grid));
  rewound.rewoundTo(3, walkAt(90));                        // a second pocket from the same state
  EXPECT_TRUE(rewound.barred(3, {0.1, 1, 0}, grid));       // 84.3 degrees
  EXPECT_TRUE(rewound.barred(3, walkAt(0), grid));         // the first walk stays barred
  EXPECT_EQ(rewound.walks(), 2u);
}

TEST(RewoundHeadings, HeadingsWrapAroundHalfATurn) {
  const CoverageGrid grid = unitGrid();
  RewoundHeadings rewound(11.25);
  rewound.rewoundTo(0, walkAt(175));
  EXPECT_TRUE(rewound.barred(0, walkAt(-175), grid));  // 10 degrees apart across +-180
  EXPECT_FALSE(rewound.barred(0, walkAt(-165), grid));
}

TEST(RewoundHeadings, ARewindFurtherBackForgetsTheStatesItDiscards) {
  const CoverageGrid grid = unitGrid();
  RewoundHeadings rewound(11.25);
  rewound.rewoundTo(5, walkAt(0));
  rewound.rewoundTo(3, walkAt(45));
  rewound.rewoundTo(1, walkAt(-90));  // the states after 3 and 5 steps are gone
  EXPECT_FALSE(rewound.barred(5, walkAt(0), grid));
  EXPECT_FALSE(rewound.barred(3, walkAt(45), grid));
  EXPECT_TRUE(rewound.barred(1, walkAt(-90), grid));
  EXPECT_EQ(rewound.walks(), 1u);
  rewound.rewoundTo(1, walkAt(0));  // back to the same state again: both kept
  EXPECT_EQ(rewound.walks(), 2u);
}

TEST(RewoundHeadings, AWalkWithoutLengthHasNoHeading) {
  const CoverageGrid grid = unitGrid();
  RewoundHeadings rewound(11.25);
  rewound.rewoundTo(2, Eigen::Vector3d::Zero());
  EXPECT_EQ(rewound.walks(), 0u);
  rewound.rewoundTo(2, walkAt(0));
  EXPECT_FALSE(rewound.barred(2, Eigen::Vector3d::Zero(), grid));
}
