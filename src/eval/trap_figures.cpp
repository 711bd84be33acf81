#include "valerant/eval/trap_figures.h"

#include <algorithm>

#include "valerant/eval/episode_truth.h"
#include "valerant/eval/spawn_departure.h"
#include "valerant/world/action_sequence.h"

namespace valerant {

int finalTurnStreak(const std::vector<StepRecord>& history) {
  int streak = 0;
  for (auto it = history.rbegin(); it != history.rend(); ++it) {
    if (committedTranslation(*it) || it->rewind) break;
    ++streak;
  }
  return streak;
}

FinalStreakWays finalStreakWays(const std::vector<StepRecord>& history, const Config& config) {
  FinalStreakWays ways;
  const size_t streak = static_cast<size_t>(finalTurnStreak(history));
  double last_yaw = 0;  // the streak's turn before, 0 before its first
  for (size_t i = history.size() - streak; i < history.size(); ++i) {
    const StepRecord& step = history[i];
    for (const CandidateRecord& c : step.candidates) {
      if (c.verdict.rotation_only || c.truth.empty()) continue;
      ++ways.translations;
      ways.clean_translations += staysOutOfSolid(c);
    }
    if (step.chosen < 0) continue;  // a stall turns nothing
    const double yaw =
        makeActionSequence(step.candidates[static_cast<size_t>(step.chosen)].verdict.candidate, config).totalYawDeg();
    ways.reversals += yaw * last_yaw < 0;
    if (yaw != 0) last_yaw = yaw;
  }
  return ways;
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
