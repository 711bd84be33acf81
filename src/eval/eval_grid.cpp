#include "valerant/eval/eval_grid.h"

#include <algorithm>
#include <map>

#include "valerant/common/error.h"
#include "valerant/common/joined.h"

namespace valerant {
namespace {

// Extra valerant_explore options per configuration.
const std::map<std::string, std::vector<std::string>>& configOptions() {
  static const std::map<std::string, std::vector<std::string>> options = {
      {"full", {}},
      {"no-rf", {"--no-rf"}},
      {"no-col", {"--no-col-pc", "--no-col-depth"}},
      {"no-col-pc", {"--no-col-pc"}},
      {"no-col-depth", {"--no-col-depth"}},
      {"no-dp", {"--no-dp"}},
      {"oracle", {"--slam", "oracle"}},
      {"random", {"--policy", "random"}},
      {"forward", {"--policy", "forward"}},
      {"frontier", {"--policy", "frontier"}},
  };
  return options;
}

}  // namespace

const std::vector<std::string>& knownEvalConfigs() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& [name, options] : configOptions()) n.push_back(name);
    return n;
  }();
  return names;
}

std::vector<EvalRun> makeEvalGrid(const std::vector<std::string>& maps, int spawns,
                                  const std::vector<std::string>& configs, const std::string& out_dir) {
  if (maps.empty()) throw InputError("--maps", "names no map");
  if (spawns < 1) throw InputError("--spawns", "must be >= 1");
  for (const auto& c : configs)
    if (!configOptions().count(c)) {
      throw InputError("configuration '" + c + "'", "unknown (known: " + joined(knownEvalConfigs()) + ")");
    }
  std::vector<EvalRun> runs;
  for (const auto& map : maps)
    for (int s = 0; s < spawns; ++s)
      for (const auto& c : configs)
        runs.push_back({map, s, c, out_dir + "/runs/" + map + "-s" + std::to_string(s) + "-" + c});
  return runs;
}

std::vector<std::string> exploreArguments(const EvalRun& run, const std::string& slam, int budget) {
  std::vector<std::string> args = {"--map", run.map, "--spawn", std::to_string(run.spawn), "--slam", slam,
                                   "--budget", std::to_string(budget), "--out", run.dir, "--force"};
  const auto& extra = configOptions().at(run.config);
  // A configuration's own --slam replaces the grid's.
  for (size_t i = 0; i < extra.size(); ++i) {
    if (extra[i] == "--slam" && i + 1 < extra.size()) {
      *(std::find(args.begin(), args.end(), "--slam") + 1) = extra[++i];
    } else {
      args.push_back(extra[i]);
    }
  }
  return args;
}

}  // namespace valerant
