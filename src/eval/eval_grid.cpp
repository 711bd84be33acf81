#include "valerant/eval/eval_grid.h"

#include <algorithm>
#include <map>
#include <set>

#include "valerant/common/error.h"
#include "valerant/common/joined.h"
#include "valerant/world/quake3/bsp.h"
#include "valerant/world/quake3/pk3_archive.h"

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

bool isPlainEvalName(const std::string& name) {
  if (name.empty() || name[0] == '.' || name.find("..") != std::string::npos) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
           c == '.';
  });
}

namespace {

// Every name of `option` is plain and named once.
void checkNames(const std::vector<std::string>& names, const std::string& option, const std::string& what) {
  std::set<std::string> seen;
  for (const auto& n : names) {
    if (!isPlainEvalName(n))
      throw InputError(option + " '" + n + "'", "is not a plain " + what +
                                                   " name (letters, digits, '_', '-' and '.', not starting with '.' "
                                                   "and without '..'): run folders are named after it");
    if (!seen.insert(n).second) throw InputError(option + " '" + n + "'", "is named twice (its runs would share a folder)");
  }
}

}  // namespace

std::vector<EvalRun> makeEvalGrid(const std::vector<std::string>& maps, int spawns,
                                  const std::vector<std::string>& configs, const std::string& out_dir) {
  if (maps.empty()) throw InputError("--maps", "names no map");
  if (spawns < 1) throw InputError("--spawns", "must be >= 1");
  checkNames(maps, "--maps", "map");
  checkNames(configs, "--configs", "configuration");
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

std::map<std::string, int> installedSpawnCounts(const std::vector<std::string>& maps) {
  quake3::Pk3FileSystem fs;
  fs.mountDirectory(quake3::Pk3FileSystem::defaultDataDir());
  std::map<std::string, int> counts;
  for (const auto& map : maps) {
    const std::string path = "maps/" + map + ".bsp";
    const auto bytes = fs.read(path);
    if (!bytes) {
      throw InputError("--maps '" + map + "'", "not found in the installed pk3s (" +
                                                   quake3::Pk3FileSystem::defaultDataDir() + ")");
    }
    counts[map] = static_cast<int>(quake3::parseBsp(*bytes, fs.archiveOf(path) + ":" + path).spawnPoints().size());
  }
  return counts;
}

void checkEvalSpawns(const std::vector<EvalRun>& runs, const std::map<std::string, int>& spawn_counts) {
  std::vector<std::string> maps;  // in grid order
  std::map<std::string, int> highest;
  for (const auto& r : runs) {
    if (!highest.count(r.map)) maps.push_back(r.map);
    highest[r.map] = std::max(highest.count(r.map) ? highest[r.map] : 0, r.spawn);
  }
  std::vector<std::string> short_maps;
  for (const auto& map : maps) {
    const auto count = spawn_counts.find(map);
    if (count == spawn_counts.end() || highest[map] < count->second) continue;
    const int n = count->second;
    short_maps.push_back(map + " has " + std::to_string(n) + " spawn point" + (n == 1 ? " (index 0)" : "s") +
                         (n > 1 ? " (indices 0 to " + std::to_string(n - 1) + ")" : ""));
  }
  if (!short_maps.empty()) {
    int spawns = 0;
    for (const auto& [map, spawn] : highest) spawns = std::max(spawns, spawn + 1);
    throw InputError("--spawns " + std::to_string(spawns),
                     "asks for spawn indices a map does not have: " + joined(short_maps, "; "));
  }
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
