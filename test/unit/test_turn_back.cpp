// turnsBack (turn_back.h) on hand-worked turns, min_turn 22.5 degrees (half of jw / lw's
// 45-degree turn). jq and lq turn 90 degrees left and right over 57 frames (1.579
// degrees a frame); jq@28 turns 44.2, lq:82 129.5.
#include <gtest/gtest.h>

#include "valerant/explore/turn_back.h"

using valerant::turnsBack;

TEST(TurnBack, TheOppositeTurnOfTheSameSizeTurnsBack) {
  EXPECT_TRUE(turnsBack(-90, 90, 22.5));   // lq then jq: back to the heading before lq
  EXPECT_TRUE(turnsBack(90, -90, 22.5));   // jq then lq
  EXPECT_TRUE(turnsBack(-90, 80, 22.5));   // ends 10 degrees short of it
}

TEST(TurnBack, ATurnEndingANewDirectionAwayDoesNot) {
  EXPECT_FALSE(turnsBack(-129.5, 90, 22.5));  // lq:82 then jq: 39.5 degrees past it
  EXPECT_FALSE(turnsBack(90, -44.2, 22.5));   // jq then lq@28: 45.8 degrees from it
  EXPECT_FALSE(turnsBack(-90, 67.5, 22.5));   // exactly 22.5 away: a new direction
}

TEST(TurnBack, TheSameWayOnIsNoTurnBack) {
  EXPECT_FALSE(turnsBack(90, 90, 22.5));
  EXPECT_FALSE(turnsBack(-10, -10, 22.5));  // small turns the same way: still on, not back
  EXPECT_FALSE(turnsBack(0, 10, 22.5));     // no last turn to undo
}
