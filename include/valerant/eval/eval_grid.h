#pragma once
// The evaluation grid of valerant_eval: every (map, spawn, configuration) run, the
// valerant_explore options that make it, and where its results live. Configurations:
//   full      the method as configured (visual SLAM unless --slam says otherwise)
//   no-rf     without robust floor estimation      no-dp    without dead-pocket rewind
//   no-col    without both collision tests          no-col-pc / no-col-depth: one of them
//   oracle    ground-truth SLAM instead of visual
//   random / forward / frontier: the baseline policies on the same SLAM and tests
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

// All runs, maps outermost; throws InputError naming an unknown configuration.
std::vector<EvalRun> makeEvalGrid(const std::vector<std::string>& maps, int spawns,
                                  const std::vector<std::string>& configs, const std::string& out_dir);

// valerant_explore arguments (without the program name) for one run.
std::vector<std::string> exploreArguments(const EvalRun& run, const std::string& slam, int budget);

}  // namespace valerant
