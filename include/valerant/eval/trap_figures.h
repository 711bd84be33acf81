#pragma once
// Two figures of how an episode ends trapped (docs/pockets.md): turning in place step
// after step, with every way out either colliding or walled off by the failed-region
// memory F. Both were counted by hand from decisions.jsonl for every 150-step grid; the
// report now carries them.
#include <vector>

#include "valerant/config/config.h"
#include "valerant/explore/episode.h"

namespace valerant {

// Steps at the end of `history` that committed a turn in place or stalled, after the
// last step that committed a translation or rewound (a rewind moves the agent): 0 when
// the last step translated or rewound, the whole history when none ever did.
int finalTurnStreak(const std::vector<StepRecord>& history);

// What the final streak (finalTurnStreak) did and met, which tells two traps apart: an
// agent swinging between two headings that both face walls (many reversals, no clean
// translation), and one whose tests or F reject open ways (many clean translations).
//   reversals: committed turns in place of the streak whose yaw has the opposite sign
//     of the streak's turn before them (a left after a right, or the reverse);
//   translations: translation candidates judged over the streak that carry truth;
//   clean_translations: those of them whose frames all stayed out of solid.
// `config` gives each chosen candidate's yaw (makeActionSequence).
struct FinalStreakWays {
  int reversals = 0;
  int translations = 0;
  int clean_translations = 0;
};
FinalStreakWays finalStreakWays(const std::vector<StepRecord>& history, const Config& config);

// Translation candidates whose only objection was F ("enters failed region", policy.cpp)
// and whose frames all stayed out of solid by the engine's truth: clean ways out that F
// alone walled off. Candidates without truth are not counted.
int cleanTranslationsBlockedByFailedRegion(const std::vector<StepRecord>& history);

// Turns the tests forced on an open way: of the steps that committed a turn in place or
// stalled (`turns`), those at which no translation was admissible while at least one
// judged translation stayed out of solid by the engine's truth (`falsely_forced`). With
// exact depth a turn is chosen because every way on collides; in the 60-step visual runs
// of docs/pockets.md nine turns in ten were forced on an open way. Steps without any
// judged translation, or whose translations carry no truth, are not falsely forced.
struct ForcedTurns {
  int turns = 0;
  int falsely_forced = 0;
};
ForcedTurns forcedTurns(const std::vector<StepRecord>& history);

// Steps that began with no goal frontier reachable (StepRecord::goal_distance), and of
// them those F alone cut off (one is reachable when F is ignored): then the frontier goal
// gives every candidate G = 0 and the paper's local terms decide alone.
struct GoalReach {
  int unreachable_steps = 0;
  int cut_off_by_failed_steps = 0;
};
GoalReach goalReach(const std::vector<StepRecord>& history);

}  // namespace valerant
