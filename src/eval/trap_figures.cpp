#include "valerant/eval/trap_figures.h"

#include <algorithm>

#include "valerant/eval/episode_truth.h"
#include "valerant/eval/spawn_departure.h"

namespace valerant {

int finalTurnStreak(const std::vector<StepRecord>& history) {
  int streak = 0;
  for (auto it = history.rbegin(); it != history.rend(); ++it) {
    if (committedTranslation(*it) || it->rewind) break;
    ++streak;
  }
  return streak;
}

int cleanTranslationsBlockedByFailedRegion(const std::vector<StepRecord>& history) {
  int blocked = 0;
  for (const StepRecord& step : history)
    for (const CandidateRecord& c : step.candidates) {
      const BranchVerdict& v = c.verdict;
      // The reason lists every objection the policy had (selectBranch), so F alone is
      // the flag set and nothing else named.
      if (v.rotation_only || !v.enters_failed || v.reason != "enters failed region") continue;
      blocked += staysOutOfSolid(c);
    }
  return blocked;
}

ForcedTurns forcedTurns(const std::vector<StepRecord>& history) {
  ForcedTurns forced;
  for (const StepRecord& step : history) {
    if (committedTranslation(step)) continue;
    ++forced.turns;
    bool admissible = false, open_way = false;
    for (const CandidateRecord& c : step.candidates) {
      if (c.verdict.rotation_only) continue;
      admissible = admissible || c.verdict.admissible;
      open_way = open_way || staysOutOfSolid(c);
    }
    forced.falsely_forced += !admissible && open_way;
  }
  return forced;
}

GoalReach goalReach(const std::vector<StepRecord>& history) {
  GoalReach reach;
  for (const StepRecord& step : history) {
    if (step.goal_distance >= 0) continue;
    ++reach.unreachable_steps;
    reach.cut_off_by_failed_steps += step.goal_distance_without_failed >= 0;
  }
  return reach;
}

}  // namespace valerant
