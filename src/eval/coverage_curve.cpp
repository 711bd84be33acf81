#include "valerant/eval/coverage_curve.h"

#include <algorithm>
#include <string>

#include "valerant/common/error.h"

namespace valerant {

CoverageCurve coverageByCommittedStep(const std::vector<StepRecord>& history,
                                      const std::vector<double>& observed_percent_by_step) {
  // An empty list: the map was never tied to the world (nothing fused), 0 % throughout.
  const std::vector<double> observed =
      observed_percent_by_step.empty() ? std::vector<double>(history.size(), 0.0) : observed_percent_by_step;
  if (history.size() != observed.size())
    throw InputError("observed_percent_by_step", std::to_string(observed_percent_by_step.size()) +
                                                     " values for " + std::to_string(history.size()) + " steps");
  CoverageCurve curve;
  double wall = 0;
  for (size_t i = 0; i < history.size(); ++i) {
    const StepRecord& step = history[i];
    wall += step.wall_seconds;
    if (step.chosen < 0 || step.rewind || step.committed_steps < 1) continue;
    const size_t k = static_cast<size_t>(step.committed_steps);
    if (curve.committed_step.size() < k) {
      curve.committed_step.resize(k);
      curve.observed_percent.resize(k);
      curve.wall_seconds.resize(k);
    }
    curve.committed_step[k - 1] = static_cast<int>(k);
    curve.observed_percent[k - 1] = observed[i];
    curve.wall_seconds[k - 1] = wall;
  }
  // Steps a later rewind dropped for good are no part of the kept path.
  const size_t kept = history.empty() ? 0 : static_cast<size_t>(std::max(0, history.back().committed_steps));
  if (curve.committed_step.size() > kept) {
    curve.committed_step.resize(kept);
    curve.observed_percent.resize(kept);
    curve.wall_seconds.resize(kept);
  }
  return curve;
}

}  // namespace valerant
