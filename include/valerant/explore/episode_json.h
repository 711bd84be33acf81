#pragma once
// JSON forms of an episode's records: one decisions.jsonl line per step with every
// candidate's verdict and score terms, and the stage timings.
#include <nlohmann/json.hpp>

#include "valerant/explore/episode.h"

namespace valerant {

nlohmann::json toJson(const BranchVerdict& v);
nlohmann::json toJson(const StageSeconds& s);
nlohmann::json toJson(const StepRecord& r);

}  // namespace valerant
