// valerant_bench: speed and memory figures, one JSON line per run on stdout.
//
//   valerant_bench render --map oa_dm1 [--frames 1000] [--spawn 0] [--config FILE] [--set key=value ...]
//     frames/s of colour + depth rendering, peak memory (bench/bench_render.cpp)
//   valerant_bench slam --map oa_dm1 [--spawn 0] [--candidates uw,jw,lw,jq,lq]
//                       [--slam visual|oracle] [--repeats 3] [--config FILE] [--set key=value ...]
//     SLAM frames/s per branch on one core and snapshot+restore cost (bench/bench_slam.cpp)
//   valerant_bench graph --map oa_dm1 [--spawn 0] [--seed 0] [--slam oracle] [--budget 5]
//                        [--config FILE] [--set key=value ...] --out DIR
//     one episode in process and through the ROS node graph: wall-time ratio and
//     whether the decisions agree (bench/bench_graph.cpp)
//   valerant_bench map --run DIR [--updates 15]
//     cost of the live map products as a finished run's map grows (bench/bench_map.cpp)
//   valerant_bench depth --maps oa_dm1,oa_dm2 [--spawns 2] [--model FILE] [--config FILE] [--set key=value ...]
//     the learned depth prior's accuracy against the engine's depth and its time per
//     frame on one thread, next to the visual SLAM's plane-sweep depth (bench/bench_depth.cpp)
//   valerant_bench extent --maps oa_dm1,oa_dm2 [--spawns 3] [--config FILE] [--set key=value ...]
//     the reachable floor's farthest distance from each spawn against the exploration
//     grid's reach: whether the coverage grid holds the whole level (bench/bench_extent.cpp)
//   valerant_bench wm [--maps A,B] [--spawns 1] [--model FILE] [--out DIR] [--config FILE] [--set key=value ...]
//     the learned world model's rollouts against the engine's from the same spawn: PSNR and
//     SSIM at five horizons next to two baselines, the visual SLAM's yaw and heading on
//     them, the depth prior on them, CPU time per frame; comparison sheets (bench/bench_wm.cpp)
//   valerant_bench sweep --map oa_dm1 [--spawn 0] [--candidates uw,jw,lw] [--gap 6] [--repeats 2]
//     plane-sweep ms per frame on one core per instruction set, and whether they agree bit
//     for bit (bench/bench_sweep.cpp)
//
// `valerant_bench --help` lists the benchmarks, `valerant_bench NAME --help` the flags of one.
#include <iostream>
#include <map>

#include "bench/bench.h"

using namespace valerant;

int main(int argc, char** argv) {
  CLI::App app{"Speed, memory and accuracy benchmarks; one JSON line on stdout.", "valerant_bench"};
  tools::useToolConventions(app);
  app.require_subcommand(1);
  const std::map<std::string, tools::BenchRun> benchmarks = {{"render", tools::addBenchRender(app)},
                                                             {"slam", tools::addBenchSlam(app)},
                                                             {"graph", tools::addBenchGraph(app)},
                                                             {"map", tools::addBenchMap(app)},
                                                             {"depth", tools::addBenchDepth(app)},
                                                             {"extent", tools::addBenchExtent(app)},
                                                             {"wm", tools::addBenchWorldModel(app)},
                                                             {"sweep", tools::addBenchSweep(app)}};
  return tools::runTool(app, argc, argv, [&] {
    std::cout << benchmarks.at(app.get_subcommands().front()->get_name())().dump() << std::endl;
    return 0;
  });
}
