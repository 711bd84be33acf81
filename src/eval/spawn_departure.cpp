#include "valerant/eval/spawn_departure.h"

namespace valerant {

bool committedTranslation(const StepRecord& step) {
  return step.chosen >= 0 && !step.candidates.at(static_cast<size_t>(step.chosen)).verdict.rotation_only;
}

int firstTranslationStep(const std::vector<StepRecord>& history) {
  for (const StepRecord& s : history)
    if (committedTranslation(s)) return s.step;
  return 0;
}

}  // namespace valerant
