#include "valerant/explore/progress_line.h"

#include <iomanip>
#include <sstream>

namespace valerant {

std::string progressLine(const StepRecord& step, const StepProgress& progress) {
  std::ostringstream line;
  line << std::fixed << "step " << step.step << " | committed " << step.committed_steps << " | "
       << (step.chosen >= 0 ? step.candidates.at(step.chosen).verdict.candidate : std::string("stall"))
       << (step.rewind ? " + rewind" : "") << (progress.as_recorded ? " (as recorded)" : "");
  if (progress.observed_percent) line << " | observed " << std::setprecision(1) << *progress.observed_percent << " %";
  line << " | keyframes " << step.map_keyframes << " | memory " << progress.resident_bytes / (1024 * 1024) << " MB | "
       << std::setprecision(2) << progress.seconds << " s, " << std::setprecision(1) << progress.total_seconds
       << " s total";
  return line.str();
}

}  // namespace valerant
