// The end clearance of a translation ([ours], collision.end_clearance, branch_check.h):
// N_occ points within the wider radius at the last frame make the translation
// inadmissible, and its clean prefix stops short of the contact; hand-worked walks.
#include <gtest/gtest.h>

#include "valerant/explore/branch_check.h"
#include "valerant/explore/committed_points.h"
#include "walking_branch.h"

using namespace valerant;
using valerant::test::edgeAt;
using valerant::test::floorBelow;
using valerant::test::trackedAtZ;

namespace {

// Rho 0.30 (0.15 units at kappa 0.5), the prefix clearance as narrow, margin 0.5 eye
// heights (0.25 units), min advance 0.1; `end_clearance` in eye heights.
Config clearanceConfig(double end_clearance) {
  Config config;
  config.collision.body_radius = 0.30;
  config.collision.prefix_clearance = 0.30;
  config.collision.prefix_margin = 0.5;
  config.collision.prefix_min_advance = 0.1;
  config.collision.end_clearance = end_clearance;
  return config;
}

// The camera walks z = 0, 0.1 .. 0.9 (kappa 0.5) past `edge`.
BranchVerdict walkTo(const Config& config, CommittedSteps edge, bool rotation_only = false) {
  BranchCheck check(config, std::move(edge));
  for (int i = 0; i < 10; ++i) {
    const TrackedFrame f = trackedAtZ(0.1 * i);
    check.add(f, nullptr, floorBelow(f.camera_to_map.translation(), 0.5));
  }
  return check.finish(rotation_only ? "jq" : "uw", rotation_only);
}

}  // namespace

// The edge at x = 0.17 beside the last camera (z = 0.9): 0.17 units from the body axis,
// outside rho's 0.15, so eq. 6 counts nothing. End clearance 0.42 (0.21 units): the last
// frame holds all 40 points, as does frame 8 (z = 0.8: sqrt(0.17^2 + 0.1^2) = 0.197),
// frame 7 none (sqrt(0.17^2 + 0.2^2) = 0.262). The contact run starts at frame 8: the
// prefix keeps the cameras 0.25 units short of z = 0.8, z <= 0.55, frames 0 to 5.
TEST(EndClearance, ATranslationEndingBesideACornerIsInContact) {
  const BranchVerdict v = walkTo(clearanceConfig(0.42), edgeAt(0.17f, 0.9f));
  EXPECT_FALSE(v.collision_pc);
  EXPECT_EQ(v.occupied_max, 0);
  EXPECT_TRUE(v.ends_in_contact);
  EXPECT_TRUE(v.predictsCollision());
  EXPECT_EQ(v.prefix_frames, 6);
  // Off (the paper): the same walk passes whole.
  const BranchVerdict off = walkTo(clearanceConfig(0), edgeAt(0.17f, 0.9f));
  EXPECT_FALSE(off.ends_in_contact);
  EXPECT_FALSE(off.predictsCollision());
  EXPECT_EQ(off.prefix_frames, 10);
}

// At x = 0.22 the edge stays outside 0.21 units of every camera: no contact.
TEST(EndClearance, AnEdgeBeyondTheClearanceIsNoContact) {
  const BranchVerdict v = walkTo(clearanceConfig(0.42), edgeAt(0.22f, 0.9f));
  EXPECT_FALSE(v.ends_in_contact);
  EXPECT_EQ(v.prefix_frames, 10);
}

// Passed on the way (z = 0.5: within 0.21 units of frames 4 to 6 only) it is no contact
// either: only where the walk ends counts.
TEST(EndClearance, OnlyTheEndPoseIsHeldToIt) {
  const BranchVerdict v = walkTo(clearanceConfig(0.42), edgeAt(0.17f, 0.5f));
  EXPECT_FALSE(v.ends_in_contact);
  EXPECT_FALSE(v.collision_pc);
  EXPECT_EQ(v.prefix_frames, 10);
}

// A turn in place is not judged by it (eq. 6 exempts rotations; the turn guards of
// collision.turn_contact_points and turn_start_points are for those).
TEST(EndClearance, TurnsAreNotJudged) {
  EXPECT_FALSE(walkTo(clearanceConfig(0.42), edgeAt(0.17f, 0.9f), true).ends_in_contact);
}
