// Candidate expansion: exact frame counts, yaw and displacement of each candidate.
#include <gtest/gtest.h>

#include "valerant/common/error.h"
#include "valerant/world/action_sequence.h"

using namespace valerant;

TEST(ActionSequence, ForwardCandidateMovesOneNominalDisplacement) {
  const Config c;
  const ActionSequence uw = makeActionSequence("uw", c);
  ASSERT_EQ(uw.steps.size(), 57u);
  EXPECT_NEAR(uw.totalForwardUnits(), 256.0, 1e-9);
  EXPECT_DOUBLE_EQ(uw.totalYawDeg(), 0.0);
  EXPECT_FALSE(uw.rotationOnly());
}

TEST(ActionSequence, TurnThenForwardCandidates) {
  const Config c;
  const ActionSequence jw = makeActionSequence("jw", c);
  const ActionSequence lw = makeActionSequence("lw", c);
  ASSERT_EQ(jw.steps.size(), 97u);  // 57 + 40
  EXPECT_NEAR(jw.totalYawDeg(), 45.0, 1e-9);
  EXPECT_NEAR(lw.totalYawDeg(), -45.0, 1e-9);
  EXPECT_NEAR(jw.totalForwardUnits(), 256.0 * 97 / 57, 1e-9);
  EXPECT_DOUBLE_EQ(jw.steps[56].yaw_deg, 45.0 / 57);
  EXPECT_DOUBLE_EQ(jw.steps[57].yaw_deg, 0.0);  // the appended segment only moves
}

TEST(ActionSequence, RotationCandidates) {
  const Config c;
  const ActionSequence jq = makeActionSequence("jq", c);
  const ActionSequence lq = makeActionSequence("lq", c);
  ASSERT_EQ(jq.steps.size(), 57u);
  EXPECT_NEAR(jq.totalYawDeg(), 90.0, 1e-9);
  EXPECT_NEAR(lq.totalYawDeg(), -90.0, 1e-9);
  EXPECT_TRUE(jq.rotationOnly());
  EXPECT_TRUE(lq.rotationOnly());
}

TEST(ActionSequence, KeyStrings) {
  const Config c;
  const ActionSequence s = makeActionSequence("w:10,d:5,k:2", c);
  ASSERT_EQ(s.steps.size(), 17u);
  EXPECT_NEAR(s.totalForwardUnits(), 10 * 256.0 / 57, 1e-9);
  EXPECT_NEAR(s.steps[10].strafe_units, 256.0 / 57, 1e-9);
  EXPECT_NEAR(s.steps[16].pitch_deg, 90.0 / 57, 1e-9);
}

TEST(ActionSequence, BadActionStringsAreNamed) {
  const Config c;
  for (const std::string bad : {"xx", "w:", ":3", "w:abc", "z:3", "w:0", "w:3x", ""}) {
    try {
      makeActionSequence(bad, c);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_EQ(e.input(), "action '" + bad + "'");
    }
  }
}

TEST(ActionSequence, CleanPrefixesAreTheirCandidatesFirstFrames) {
  const Config c;
  const ActionSequence uw31 = makeActionSequence("uw@31", c);
  ASSERT_EQ(uw31.steps.size(), 31u);
  EXPECT_EQ(uw31.name, "uw@31");
  EXPECT_NEAR(uw31.totalForwardUnits(), 31 * 256.0 / 57, 1e-9);
  // jw@60: the whole 57-frame turn (45 degrees) and 3 frames of the forward tail.
  const ActionSequence jw60 = makeActionSequence(prefixName("jw", 60), c);
  ASSERT_EQ(jw60.steps.size(), 60u);
  EXPECT_NEAR(jw60.totalYawDeg(), 45.0, 1e-9);
  EXPECT_NEAR(jw60.totalForwardUnits(), 60 * 256.0 / 57, 1e-9);
  EXPECT_EQ(baseCandidate("jw@60"), "jw");
  EXPECT_EQ(baseCandidate("lq"), "lq");
  for (const std::string bad : {"uw@0", "uw@57", "jw@97", "xx@3", "uw@3x", "uw@", "w:3@2"}) {
    try {
      makeActionSequence(bad, c);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_EQ(e.input(), "action '" + bad + "'");
    }
  }
}

TEST(ActionSequence, TurnsOfAnyLengthRunOnTheirCandidatesBranch) {
  const Config c;  // jq / lq turn 90 degrees over 57 frames: 90/57 degrees a frame
  // 180 degrees right: 180 / (90/57) = 114 frames.
  EXPECT_EQ(turnName(-180.0, c), "lq:114");
  EXPECT_EQ(turnName(45.0, c), "jq:29");   // 28.5 rounds up
  EXPECT_EQ(turnName(0.2, c), "jq:1");     // at least one frame
  const ActionSequence right = makeActionSequence("lq:114", c);
  ASSERT_EQ(right.steps.size(), 114u);
  EXPECT_NEAR(right.totalYawDeg(), -180.0, 1e-9);
  EXPECT_TRUE(right.rotationOnly());
  EXPECT_EQ(baseCandidate("lq:114"), "lq");
  EXPECT_EQ(baseCandidate("jq:29"), "jq");
  // Short turns are prefixes: jq@28 turns 28 * 90/57 degrees.
  EXPECT_NEAR(makeActionSequence("jq@28", c).totalYawDeg(), 28 * 90.0 / 57, 1e-9);
}

TEST(ActionSequence, GoalMovesTurnThenWalkOnUwsBranch) {
  const Config c;  // 90/57 degrees a frame in place; 8 cells (one forward action) in 57 frames
  // 36 degrees right: 36 / (90/57) = 22.8 -> 23 frames; 5.75 cells: 5.75 / 8 * 57 = 40.97 -> 41.
  EXPECT_EQ(goalMoveName(-36.0, 5.75, c), "l:23,w:41");
  EXPECT_EQ(goalMoveName(0.5, 5.75, c), "w:41");      // 0.32 frames of turn: none
  EXPECT_EQ(goalMoveName(90.0, 0.05, c), "j:57,w:1");  // at least one frame of walk
  const ActionSequence move = makeActionSequence("l:23,w:41", c);
  ASSERT_EQ(move.steps.size(), 64u);
  EXPECT_NEAR(move.totalYawDeg(), -23 * 90.0 / 57, 1e-9);
  EXPECT_NEAR(move.totalForwardUnits(), 41 * 256.0 / 57, 1e-9);
  EXPECT_DOUBLE_EQ(move.steps[22].forward_units, 0.0);  // the turn is in place ...
  EXPECT_DOUBLE_EQ(move.steps[23].yaw_deg, 0.0);        // ... then the walk is straight
  // Key strings run on the branch of the candidate they are like.
  EXPECT_EQ(baseCandidate("l:23,w:41"), "uw");
  EXPECT_EQ(baseCandidate("w:40"), "uw");
  EXPECT_EQ(baseCandidate("j:3,l:5"), "lq");  // net 2 frames right
  EXPECT_EQ(baseCandidate("q:3"), "jq");
  EXPECT_EQ(baseCandidate("nonsense"), "nonsense");  // no KEYS:FRAMES: returned whole
}

TEST(ActionSequence, DescriptionsSayWhatAnActionDoes) {
  const Config c;  // 256 units (8 m) over 57 frames; jw's tail 40 frames
  EXPECT_EQ(describeAction("lq:114", c), "lq:114 (turn 180 deg right)");
  EXPECT_EQ(describeAction("uw@32", c), "uw@32 (4.5 m forward)");  // 32 * 8 / 57 = 4.49
  EXPECT_EQ(describeAction("jw", c), "jw (turn 45 deg left, 13.6 m forward)");  // 97 * 8 / 57 = 13.61
  EXPECT_EQ(describeAction("q:3", c), "q:3 (no motion)");
}

// Where a branch of one candidate is worth keeping for another (resume_points.h).
TEST(ActionSequence, SharedFramesAreTheLeadingEqualSteps) {
  const Config c;
  auto seq = [&c](const std::string& name) { return makeActionSequence(name, c); };
  EXPECT_EQ(sharedFrames(seq("uw"), seq("uw@32")), 32u);  // a short translation: uw's first 32 frames
  EXPECT_EQ(sharedFrames(seq("uw@32"), seq("uw@16")), 16u);
  EXPECT_EQ(sharedFrames(seq("jw"), seq("jw@60")), 60u);  // the turn and 3 frames of the forward tail
  EXPECT_EQ(sharedFrames(seq("jq"), seq("jq:114")), 57u);  // a longer turn continues jq
  EXPECT_EQ(sharedFrames(seq("jq"), seq("jq@28")), 28u);
  EXPECT_EQ(sharedFrames(seq("uw"), seq("jw")), 0u);       // jw turns from its first frame
  EXPECT_EQ(sharedFrames(seq("jq"), seq("lq")), 0u);
  EXPECT_EQ(sharedFrames(seq("uw"), seq("uw")), 57u);
}
