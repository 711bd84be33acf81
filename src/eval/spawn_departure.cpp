#include "valerant/eval/spawn_departure.h"

namespace valerant {

int firstTranslationStep(const std::vector<StepRecord>& history) {
  for (const StepRecord& s : history)
    if (s.chosen >= 0 && !s.candidates.at(static_cast<size_t>(s.chosen)).verdict.rotation_only) return s.step;
  return 0;
}

}  // namespace valerant
