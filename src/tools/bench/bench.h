#pragma once
// The benchmarks of valerant_bench, one per file. Each adds its subcommand and flags to
// the tool's command line and returns the run that reads them and returns the JSON
// line the tool prints.
#include <functional>
#include <nlohmann/json.hpp>

#include "../command_line.h"

namespace valerant::tools {

using BenchRun = std::function<nlohmann::json()>;

BenchRun addBenchRender(CLI::App& bench);
BenchRun addBenchSlam(CLI::App& bench);
BenchRun addBenchGraph(CLI::App& bench);
BenchRun addBenchMap(CLI::App& bench);
BenchRun addBenchDepth(CLI::App& bench);
BenchRun addBenchExtent(CLI::App& bench);
BenchRun addBenchWorldModel(CLI::App& bench);
BenchRun addBenchSweep(CLI::App& bench);

// Peak resident memory of this process so far.
double peakResidentMiB();

// Restricts this process to the first CPU it may run on, so "per core" is literal;
// returns that CPU, -1 if it could not.
int pinToOneCpu();

}  // namespace valerant::tools
