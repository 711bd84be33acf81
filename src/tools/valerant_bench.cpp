// valerant_bench: speed and memory figures, one JSON line per run on stdout.
//
//   valerant_bench render --map oa_dm1 [--frames 1000] [--spawn 0] [--config FILE]
//     frames/s of colour + depth rendering, peak memory (bench/bench_render.cpp)
//   valerant_bench slam --map oa_dm1 [--spawn 0] [--candidates uw,jw,lw,jq,lq]
//                       [--slam visual|oracle] [--repeats 3] [--config FILE]
//     SLAM frames/s per branch on one core and snapshot+restore cost (bench/bench_slam.cpp)
//   valerant_bench graph --map oa_dm1 [--spawn 0] [--seed 0] [--slam oracle] [--budget 5]
//                        [--config FILE] --out DIR
//     one episode in process and through the ROS node graph: wall-time ratio and
//     whether the decisions agree (bench/bench_graph.cpp)
//   valerant_bench map --run DIR [--updates 15]
//     cost of the live map products as a finished run's map grows (bench/bench_map.cpp)
//   valerant_bench depth --maps oa_dm1,oa_dm2 [--spawns 2] [--model FILE] [--config FILE]
//     the learned depth prior's accuracy against the engine's depth and its time per
//     frame on one thread, next to the visual SLAM's plane-sweep depth (bench/bench_depth.cpp)
#include <iostream>

#include "bench/bench.h"
#include "valerant/common/error.h"

using namespace valerant;

int main(int argc, char** argv) {
  try {
    if (argc < 2) throw InputError("valerant_bench", "usage: valerant_bench render|slam|graph|map|depth [options]");
    const std::string what = argv[1];
    nlohmann::json result;
    if (what == "render") {
      result = tools::benchRender(argc - 1, argv + 1);
    } else if (what == "slam") {
      result = tools::benchSlam(argc - 1, argv + 1);
    } else if (what == "graph") {
      result = tools::benchGraph(argc - 1, argv + 1);
    } else if (what == "map") {
      result = tools::benchMap(argc - 1, argv + 1);
    } else if (what == "depth") {
      result = tools::benchDepth(argc - 1, argv + 1);
    } else {
      throw InputError("valerant_bench " + what, "unknown benchmark (known: render, slam, graph, map, depth)");
    }
    std::cout << result.dump() << std::endl;
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "valerant_bench: error: " << e.what() << std::endl;
    return 1;
  }
}
