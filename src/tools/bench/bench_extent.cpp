// valerant_bench extent: for each map and each of its first N spawns, the reachable
// floor's farthest horizontal distance from the spawn against the exploration grid's
// reach (eval/level_extent.h): does the coverage grid hold the whole level?
#include <algorithm>
#include <memory>

#include "../tool_config.h"
#include "bench.h"
#include "valerant/eval/level_extent.h"
#include "valerant/world/quake3/quake3_map.h"

namespace valerant::tools {
namespace {

nlohmann::json runExtentBench(const Config& config, const std::vector<std::string>& maps, int spawns) {
  nlohmann::json rows = nlohmann::json::array();
  int needed = 0;
  bool all_fit = true;
  for (const std::string& name : maps) {
    const auto map = quake3::loadQuake3Map(name, config.world.patch_level);
    const auto points = map->bsp.spawnPoints();
    for (int s = 0; s < spawns && s < static_cast<int>(points.size()); ++s) {
      const LevelExtent e =
          levelExtent(quake3::floodFillReachableFloor(*map->collision, points[s].origin), points[s].origin, config);
      rows.push_back({{"map", name},
                      {"spawn", s},
                      {"reachable_m2", e.reachable_m2},
                      {"farthest_m", e.farthest_m},
                      {"grid_cells_needed", e.grid_cells_needed},
                      {"fits", e.fits},
                      {"spawn_storey_percent", e.spawn_storey_percent},
                      {"above_percent", e.above_percent},
                      {"below_percent", e.below_percent}});
      needed = std::max(needed, e.grid_cells_needed);
      all_fit = all_fit && e.fits;
    }
  }
  return {{"bench", "extent"},
          {"grid_cells", config.policy.grid_cells},
          {"grid_reach_m", levelExtent({}, Eigen::Vector3f::Zero(), config).grid_reach_m},
          {"grid_cells_needed", needed},
          {"all_fit", all_fit},
          {"spawns", rows}};
}

}  // namespace

BenchRun addBenchExtent(CLI::App& bench) {
  CLI::App* app = bench.add_subcommand("extent",
                                       "the reachable floor's farthest distance from each spawn against the "
                                       "exploration grid's reach");
  auto tool_config = std::make_shared<ToolConfig>(*app);
  auto maps = std::make_shared<std::string>();
  auto spawns = std::make_shared<int>(3);
  const CLI::Option* maps_flag =
      app->add_option("--maps", *maps, "maps, comma-separated (default: the configuration's world.map)")
          ->type_name("LIST");
  addInteger(*app, "--spawns", *spawns, "spawn points 0 to N-1 of every map", 1);
  return [=] {
    const Config config = tool_config->document().parse();
    return runExtentBench(config, maps_flag->count() ? commaList("--maps", *maps) : std::vector<std::string>{config.world.map},
                          *spawns);
  };
}

}  // namespace valerant::tools
