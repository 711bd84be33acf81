#pragma once
// When an episode first left its spawn: the exploration step (StepRecord::step, stalls
// counted) of its first committed translation, i.e. the first committed candidate that
// is not a turn in place. A later rewind may discard that step; it still counts, because
// the agent did walk out (issue 25's "every run leaves its spawn": a committed
// translation within the first kSpawnDepartureSteps steps).
#include <vector>

#include "valerant/explore/episode.h"

namespace valerant {

constexpr int kSpawnDepartureSteps = 5;

// Whether `step` committed a translation: a candidate that is not a turn in place.
bool committedTranslation(const StepRecord& step);

// 0 when no step of `history` committed a translation.
int firstTranslationStep(const std::vector<StepRecord>& history);

}  // namespace valerant
