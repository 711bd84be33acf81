#pragma once
// The benchmarks of valerant_bench, one per file; each parses its own options and
// returns the JSON line the tool prints.
#include <nlohmann/json.hpp>

namespace valerant::tools {

nlohmann::json benchRender(int argc, char** argv);
nlohmann::json benchSlam(int argc, char** argv);
nlohmann::json benchGraph(int argc, char** argv);
nlohmann::json benchMap(int argc, char** argv);
nlohmann::json benchDepth(int argc, char** argv);

// Peak resident memory of this process so far.
double peakResidentMiB();

}  // namespace valerant::tools
