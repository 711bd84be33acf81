// How an episode ends trapped (trap_figures.h), on hand-made histories.
#include <gtest/gtest.h>

#include "valerant/eval/trap_figures.h"

using namespace valerant;

namespace {

enum class Move { kTurn, kTranslation, kStall };

// Exploration step `number` that commits a turn in place, a translation, or stalls;
// `rewind`: the step ended in a rewind.
StepRecord step(int number, Move move, bool rewind = false) {
  StepRecord s;
  s.step = number;
  CandidateRecord turn, walk;
  turn.verdict.rotation_only = true;
  s.candidates = {turn, walk};
  s.chosen = move == Move::kTurn ? 0 : move == Move::kTranslation ? 1 : -1;
  s.rewind = rewind;
  return s;
}

// A candidate with `frames` frames of truth, the in-solid ones at `in_solid` indices,
// rejected for `reason` (the flag of F set when the reason names it).
CandidateRecord candidate(bool rotation_only, const std::string& reason, int frames, std::vector<int> in_solid = {}) {
  CandidateRecord c;
  c.verdict.rotation_only = rotation_only;
  c.verdict.reason = reason;
  c.verdict.admissible = reason.empty();
  c.verdict.enters_failed = reason.find("enters failed region") != std::string::npos;
  c.truth.resize(static_cast<size_t>(frames));
  for (int i : in_solid) c.truth[static_cast<size_t>(i)].in_solid = true;
  return c;
}

}  // namespace

TEST(TrapFigures, TheFinalStreakCountsTurnsAndStallsAfterTheLastTranslationOrRewind) {
  // Translation, turn, turn with a rewind, then turn, stall, turn: 3 steps from step 4.
  EXPECT_EQ(finalTurnStreak({step(1, Move::kTranslation), step(2, Move::kTurn), step(3, Move::kTurn, true),
                             step(4, Move::kTurn), step(5, Move::kStall), step(6, Move::kTurn)}),
            3);
  // The last step translated: no streak; it rewound: none either.
  EXPECT_EQ(finalTurnStreak({step(1, Move::kTurn), step(2, Move::kTranslation)}), 0);
  EXPECT_EQ(finalTurnStreak({step(1, Move::kTranslation), step(2, Move::kTurn, true)}), 0);
}

TEST(TrapFigures, AHistoryThatNeverTranslatedIsOneStreak) {
  EXPECT_EQ(finalTurnStreak({}), 0);
  EXPECT_EQ(finalTurnStreak({step(1, Move::kTurn), step(2, Move::kStall), step(3, Move::kTurn)}), 3);
}

TEST(TrapFigures, TheFinalStreakCountsItsReversalsAndTheCleanWaysItMet) {
  // A step committing the candidate named `chosen` (empty: a stall) beside one judged
  // translation `walk`.
  auto decided = [](const std::string& chosen, CandidateRecord walk) {
    StepRecord s;
    CandidateRecord turn;
    turn.verdict.rotation_only = true;
    turn.verdict.candidate = chosen.empty() ? "jq" : chosen;
    walk.verdict.candidate = "uw";
    s.candidates = {turn, walk};
    s.chosen = chosen.empty() ? -1 : 0;
    return s;
  };
  const std::vector<StepRecord> history = {
      // Before the streak: a committed translation (its clean candidate is not counted).
      [&] {
        StepRecord s = decided("jq", candidate(false, "", 4));
        s.chosen = 1;
        return s;
      }(),
      decided("jq", candidate(false, "enters failed region", 4)),        // the streak's first turn; clean
      decided("lq", candidate(false, "point-cloud collision", 4, {2})),  // reversal 1; a wall
      decided("lq", candidate(false, "point-cloud collision", 0)),       // same way; no truth: not judged
      decided("", candidate(false, "point-cloud collision", 4, {0})),    // a stall; a wall
      decided("jq@28", candidate(false, "enters failed region", 4)),     // reversal 2 (against lq); clean
      decided("jq:114", candidate(false, "point-cloud collision", 4, {3})),  // same way
  };
  const Config config;
  const FinalStreakWays ways = finalStreakWays(history, config);
  EXPECT_EQ(ways.reversals, 2);
  EXPECT_EQ(ways.translations, 5);
  EXPECT_EQ(ways.clean_translations, 2);
  // No streak: nothing counted.
  const FinalStreakWays none = finalStreakWays({history.front()}, config);
  EXPECT_EQ(none.reversals + none.translations + none.clean_translations, 0);
}

TEST(TrapFigures, CleanTranslationsThatOnlyTheFailedRegionRejected) {
  StepRecord a, b;
  a.candidates = {
      candidate(false, "enters failed region", 4),                        // counted: clean, F alone
      candidate(false, "enters failed region", 4, {3}),                   // its last frame in solid
      candidate(false, "point-cloud collision;enters failed region", 4),  // another objection too
      candidate(true, "enters failed region", 4),                         // a turn
      candidate(false, "", 4),                                            // admissible
  };
  b.candidates = {
      candidate(false, "enters failed region", 0),   // no truth: not judged
      candidate(false, "enters failed region", 57),  // counted
  };
  EXPECT_EQ(cleanTranslationsBlockedByFailedRegion({a, b}), 2);
  EXPECT_EQ(cleanTranslationsBlockedByFailedRegion({}), 0);
}

TEST(TrapFigures, TurnsForcedOnAnOpenWay) {
  // A step whose candidates are `candidates`, committing candidate `chosen` (-1: stall).
  auto decided = [](std::vector<CandidateRecord> candidates, int chosen) {
    StepRecord s;
    s.candidates = std::move(candidates);
    s.chosen = chosen;
    return s;
  };
  const CandidateRecord turn = candidate(true, "", 4);
  const std::vector<StepRecord> history = {
      // 1. Turned although a translation was admissible: chosen, not forced.
      decided({turn, candidate(false, "", 4)}, 0),
      // 2. Every translation rejected, one of them clean by truth: forced on an open way.
      decided({turn, candidate(false, "point-cloud collision", 4), candidate(false, "enters failed region", 4, {3})},
              0),
      // 3. Every translation rejected and each one enters solid: a wall, rightly forced.
      decided({turn, candidate(false, "point-cloud collision", 4, {2, 3})}, 0),
      // 4. A stall with a clean translation rejected: forced on an open way.
      decided({turn, candidate(false, "short action not clear to its end", 57)}, -1),
      // 5. Committed a translation: no turn.
      decided({turn, candidate(false, "", 4)}, 1),
      // 6. Rejected translations without truth, and a turn with no translation judged.
      decided({turn, candidate(false, "point-cloud collision", 0)}, 0),
      decided({turn}, 0),
  };
  const ForcedTurns forced = forcedTurns(history);
  EXPECT_EQ(forced.turns, 6);  // steps 1-4, 6 and 7
  EXPECT_EQ(forced.falsely_forced, 2);  // steps 2 and 4
  EXPECT_EQ(forcedTurns({}).turns, 0);
}

TEST(TrapFigures, StepsWithNoGoalReachableAndThoseFAloneCutOff) {
  auto goal = [](double with_f, double without_f) {
    StepRecord s;
    s.goal_distance = with_f;
    s.goal_distance_without_failed = without_f;
    return s;
  };
  // Reachable (0 is a frontier underfoot); none reachable either way; cut off by F alone,
  // twice.
  const GoalReach reach = goalReach({goal(4, 4), goal(0, 0), goal(-1, -1), goal(-1, 7.5), goal(-1, 0)});
  EXPECT_EQ(reach.unreachable_steps, 3);
  EXPECT_EQ(reach.cut_off_by_failed_steps, 2);
  EXPECT_EQ(goalReach({}).unreachable_steps, 0);
}
