// The step an episode first committed a translation, on hand-made histories.
#include <gtest/gtest.h>

#include "valerant/eval/spawn_departure.h"

using namespace valerant;

namespace {

// Exploration step `step` that commits a turn in place, a translation, or stalls.
enum class Move { kTurn, kTranslation, kStall };
StepRecord step(int number, Move move) {
  StepRecord s;
  s.step = number;
  CandidateRecord turn, walk;
  turn.verdict.rotation_only = true;
  walk.verdict.rotation_only = false;
  s.candidates = {turn, walk};
  s.chosen = move == Move::kTurn ? 0 : move == Move::kTranslation ? 1 : -1;
  return s;
}

}  // namespace

TEST(SpawnDeparture, TheFirstCommittedTranslationsStep) {
  // Two turns, a stall, then a translation at step 4 and another at 5.
  EXPECT_EQ(firstTranslationStep({step(1, Move::kTurn), step(2, Move::kTurn), step(3, Move::kStall),
                                  step(4, Move::kTranslation), step(5, Move::kTranslation)}),
            4);
  EXPECT_EQ(firstTranslationStep({step(1, Move::kTranslation)}), 1);
}

TEST(SpawnDeparture, NoTranslationIsZero) {
  EXPECT_EQ(firstTranslationStep({}), 0);
  EXPECT_EQ(firstTranslationStep({step(1, Move::kTurn), step(2, Move::kStall), step(3, Move::kTurn)}), 0);
}
