// valerant_bench map: the cost of keeping the live map products (voxel cloud, OctoMap,
// floor grid) current while an episode grows, replaying a finished run's keyframes in
// `--updates` equal groups as map_fusion receives them: rebuilt from every keyframe
// after each update (MapFusion) against extended by the new ones (LiveMap), and whether
// the two end with the same products. The configuration is the run's own (its
// config.yaml), so no --config or --set.
#include <octomap/ColorOcTree.h>

#include <memory>
#include <tuple>

#include "../thread_clock.h"
#include "bench.h"
#include "valerant/map/live_map.h"
#include "valerant/map/run_map.h"

namespace valerant::tools {

namespace {

// Every leaf's key, depth, occupancy and colour, in the tree's own order.
using Leaf = std::tuple<uint16_t, uint16_t, uint16_t, unsigned, float, uint8_t, uint8_t, uint8_t>;
std::vector<Leaf> leaves(const octomap::ColorOcTree& tree) {
  std::vector<Leaf> out;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    const octomap::OcTreeKey key = it.getKey();
    const auto colour = it->getColor();
    out.emplace_back(key[0], key[1], key[2], it.getDepth(), it->getLogOdds(), colour.r, colour.g, colour.b);
  }
  return out;
}

bool sameCloud(const std::vector<FusedPoint>& a, const std::vector<FusedPoint>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].position != b[i].position || a[i].rgb != b[i].rgb || a[i].confidence != b[i].confidence ||
        a[i].h != b[i].h)
      return false;
  return true;
}

nlohmann::json runMapBench(const std::string& dir, long updates) {
  const RunMap run = loadRunMap(dir);
  const Config& config = run.config;
  const CoverageGrid grid = run.grid();
  const double kappa = run.frame.anchorFloor().cameraHeight();
  const auto& all = run.map.keyframes();

  double rebuild_s = 0, live_s = 0;
  MapFusion rebuilt(config.map, config.collision);
  LiveMap live(config.map, config.collision, grid, kappa);
  std::vector<std::shared_ptr<const FusedKeyframe>> episode;
  std::vector<FusedPoint> rebuilt_cloud, live_cloud;
  std::unique_ptr<octomap::ColorOcTree> rebuilt_tree;
  FloorGrid rebuilt_grid, live_grid;
  for (long u = 1; u <= updates; ++u) {
    const size_t until = all.size() * u / updates;
    while (episode.size() < until) {
      episode.push_back(all[episode.size()]);
      rebuilt.add(episode.back());
    }
    ThreadClock start = ThreadClock::now();
    rebuilt_cloud = rebuilt.voxelCloud(config.map.voxel_eye_heights * kappa);
    rebuilt_tree = rebuilt.octree(config.map.octree_eye_heights * kappa);
    rebuilt_grid = rebuilt.floorGrid(grid, config.map.grid_cell_fraction * grid.cellSize());
    rebuild_s += (ThreadClock::now() - start).wall;
    start = ThreadClock::now();
    live.update(episode);
    live_cloud = live.voxelCloud();
    live_grid = live.floorGrid();
    live_s += (ThreadClock::now() - start).wall;
  }
  const bool same = sameCloud(rebuilt_cloud, live_cloud) && rebuilt_grid.cells == live_grid.cells &&
                    leaves(*rebuilt_tree) == leaves(live.octree());
  return {{"bench", "map"},
          {"run", dir},
          {"keyframes", all.size()},
          {"points", run.map.pointCount()},
          {"updates", updates},
          {"rebuild_seconds", rebuild_s},
          {"live_seconds", live_s},
          {"speedup", rebuild_s / live_s},
          {"same_products", same},
          {"peak_rss_mib", peakResidentMiB()}};
}

}  // namespace

BenchRun addBenchMap(CLI::App& bench) {
  CLI::App* app = bench.add_subcommand("map",
                                       "cost of the live map products (cloud, OctoMap, floor grid) as a "
                                       "finished run's map grows");
  auto dir = std::make_shared<std::string>();
  auto updates = std::make_shared<long>(15);
  addPath(*app, "--run", *dir, "finished run folder", "DIR")->required();
  addInteger(*app, "--updates", *updates, "equal groups the keyframes arrive in", 1L);
  return [dir, updates] { return runMapBench(*dir, *updates); };
}

}  // namespace valerant::tools
