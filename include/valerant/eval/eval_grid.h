#pragma once
// The evaluation grid of valerant_eval: every (map, spawn, configuration) run, the
// valerant_explore options that make it, and where its results live. A configuration is
// a list of configuration overrides (`floor.enabled=false`), passed to valerant_explore
// as `--set`: the loader the config file, the tools' flags and the ROS graph's launch
// arguments go through. Configurations:
//   full      the method as configured (visual SLAM unless --slam says otherwise)
//   no-rf     without robust floor estimation      no-dp    without dead-pocket rewind
//   no-col    without both collision tests          no-col-pc / no-col-depth: one of them
//   oracle    ground-truth SLAM instead of visual
//   random / forward / frontier: the baseline policies on the same SLAM and tests
#include <map>
#include <string>
#include <vector>

namespace valerant {

struct EvalRun {
  std::string map;
  int spawn = 0;
  std::string config;
  std::string dir;  // run directory under the grid's output folder
};

const std::vector<std::string>& knownEvalConfigs();

// Whether `name` may name a run folder: letters, digits, '_', '-' and '.', not starting
// with '.' and without "..", so no name reaches outside the grid's folder.
bool isPlainEvalName(const std::string& name);

// All runs, maps outermost. Throws InputError, before any run exists, naming a map or
// configuration that is not a plain name (isPlainEvalName), one named twice (two runs
// would share a folder), or an unknown configuration.
std::vector<EvalRun> makeEvalGrid(const std::vector<std::string>& maps, int spawns,
                                  const std::vector<std::string>& configs, const std::string& out_dir);

// The spawn points of each of `maps` in the installed OpenArena pk3s, the ones
// valerant_explore loads (only the BSP is parsed). Throws InputError naming a map that
// is not installed.
std::map<std::string, int> installedSpawnCounts(const std::vector<std::string>& maps);

// Throws InputError listing every map of `runs` whose spawn count (`spawn_counts`) has no
// spawn index a run asks for; a map missing from `spawn_counts` is not checked.
void checkEvalSpawns(const std::vector<EvalRun>& runs, const std::map<std::string, int>& spawn_counts);

// The overrides (key=value) that make configuration `config`; InputError if unknown.
const std::vector<std::string>& evalConfigOverrides(const std::string& config);

// valerant_explore arguments (without the program name) for one run: the grid's map,
// spawn, SLAM and budget as flags, then the configuration's overrides as `--set`.
std::vector<std::string> exploreArguments(const EvalRun& run, const std::string& slam, int budget);

}  // namespace valerant
