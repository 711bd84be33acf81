// valerant_dataset: renders training data for the learned parts (the depth prior, a
// world model) from the engine: colour frames, ground-truth depth, poses, keys and
// in-solid flags along candidate rollouts, turns in place and random walks, written as
// compact shards (shard_writer.h). Maps come from config/map_sets.yaml's split: `train`
// is every installed map except the held-out ones, `evaluation` the evaluation maps.
// One JSON line on stdout; progress on stderr.
//
// --texture-shuffle P (training split only; 0 to 1): domain randomisation. Per sequence
// each opaque surface's shader wears, with probability P, another image from the pool of
// every training map's opaque images (tinted half the time) or, a fifth of those times,
// a flat random colour (dataset/texture_shuffle.h); deterministic from --seed.
//
//   valerant_dataset --out DIR [--split train|evaluation] [--maps A,B,...] [--exclude A,B]
//                    [--seed N] [--width 128] [--height 96] [--spawns 3] [--rotations 12]
//                    [--walks 12] [--shard-mib 24] [--in-solid skip|keep] [--config FILE]
//                    [--texture-shuffle P]
//   valerant_dataset --list-maps [--split ...] [--maps ...] [--exclude ...]   (the maps, one a line)
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli_args.h"
#include "valerant/dataset/dataset_render.h"
#include "valerant/dataset/map_sets.h"
#include "valerant/world/quake3/units.h"

using namespace valerant;
namespace fs = std::filesystem;

namespace {

std::vector<std::string> chooseMaps(const tools::CliArgs& args, const dataset::MapSets& sets, const std::string& split) {
  std::vector<std::string> maps;
  if (args.has("--maps")) {
    maps = args.list("--maps", "");
  } else if (split == "evaluation") {
    maps = sets.evaluation;
  } else {
    for (const auto& m : quake3::installedMapNames())
      if (!sets.isHeldOut(m)) maps.push_back(m);
  }
  if (args.has("--exclude")) {
    const auto exclude = args.list("--exclude", "");
    maps.erase(std::remove_if(maps.begin(), maps.end(),
                              [&](const std::string& m) { return std::count(exclude.begin(), exclude.end(), m) > 0; }),
               maps.end());
  }
  for (const auto& m : maps) {
    if (split == "train" && sets.isHeldOut(m))
      throw InputError("--maps " + m, "is held out for evaluation (config/map_sets.yaml): never in a training shard");
    if (split == "evaluation" && !sets.isHeldOut(m))
      throw InputError("--maps " + m, "is not a held-out map; an evaluation shard holds only those");
  }
  if (maps.empty()) throw InputError("--maps", "no map left to render");
  return maps;
}

double probability(const tools::CliArgs& args, const std::string& key) {
  const std::string text = args.get(key, "0");
  char* end = nullptr;
  const double p = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !(p >= 0.0 && p <= 1.0))
    throw InputError(key + " " + text, "must be a probability from 0 to 1");
  return p;
}

int positive(const tools::CliArgs& args, const std::string& key, int fallback) {
  const int v = args.integer(key, fallback);
  if (v < 0) throw InputError(key + " " + std::to_string(v), "must not be negative");
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    tools::CliArgs args(argc, argv,
                        {"--out", "--split", "--maps", "--exclude", "--seed", "--width", "--height", "--spawns",
                         "--rotations", "--walks", "--shard-mib", "--in-solid", "--config", "--map-sets",
                         "--texture-shuffle"},
                        {"--list-maps"});
    Config config = loadConfig(args.get("--config", defaultConfigPath()));
    const std::string split = args.get("--split", "train");
    if (split != "train" && split != "evaluation") throw InputError("--split " + split, "must be train or evaluation");
    const std::string in_solid = args.get("--in-solid", "skip");
    if (in_solid != "skip" && in_solid != "keep") throw InputError("--in-solid " + in_solid, "must be skip or keep");
    const dataset::MapSets sets = dataset::loadMapSets(args.get("--map-sets", dataset::defaultMapSetsPath()));
    const std::vector<std::string> maps = chooseMaps(args, sets, split);
    if (args.has("--list-maps")) {
      for (const auto& m : maps) std::cout << m << '\n';
      return 0;
    }
    config.world.width = args.integer("--width", 128);
    config.world.height = args.integer("--height", 96);
    if (config.world.width < 16 || config.world.height < 16 || config.world.width > 4096 || config.world.height > 4096)
      throw InputError("--width/--height", "must be 16 to 4096 pixels");
    const int64_t seed_arg = args.integer<int64_t>("--seed", 0);
    if (seed_arg < 0) throw InputError("--seed " + std::to_string(seed_arg), "must not be negative");
    const uint64_t seed = static_cast<uint64_t>(seed_arg);
    dataset::SamplingParams params;
    params.spawns = positive(args, "--spawns", params.spawns);
    params.rotations = positive(args, "--rotations", params.rotations);
    params.walks = positive(args, "--walks", params.walks);
    const int shard_mib = args.integer("--shard-mib", 24);
    if (shard_mib < 1 || shard_mib > 60) throw InputError("--shard-mib " + std::to_string(shard_mib), "must be 1 to 60");
    const double texture_shuffle = probability(args, "--texture-shuffle");
    if (texture_shuffle > 0 && split != "train")
      throw InputError("--texture-shuffle", "randomises training data only; an evaluation shard shows the maps as they are");
    const std::string out = args.required("--out");
    fs::create_directories(out);

    // The pool is every training map's, whichever maps this run renders, so runs over
    // parts of the list draw from the same images.
    dataset::TexturePool pool;
    dataset::TextureShuffle shuffle;
    if (texture_shuffle > 0) {
      std::vector<std::string> pool_maps;
      for (const auto& m : quake3::installedMapNames())
        if (!sets.isHeldOut(m)) pool_maps.push_back(m);
      quake3::Pk3FileSystem pk3;
      pk3.mountDirectory(quake3::Pk3FileSystem::defaultDataDir());
      pool = dataset::buildTexturePool(pk3, pool_maps);
      shuffle.pool = &pool;
      shuffle.probability = texture_shuffle;
      std::cerr << "valerant_dataset: texture pool of " << pool.images.size() << " images from " << pool_maps.size()
                << " training maps\n";
    }

    dataset::ShardMeta meta;
    meta.intrinsics = CameraIntrinsics::fromHorizontalFov(config.world.width, config.world.height, config.world.fov_x_deg);
    meta.seed = seed;
    meta.split = split;
    meta.eye_height_m = config.world.eye_height_units / quake3::kUnitsPerMetre;
    meta.texture_shuffle = texture_shuffle;

    std::vector<std::string> shards;
    std::unique_ptr<dataset::ShardWriter> shard;
    auto finishShard = [&] {
      if (shard && shard->frames() > 0) shard->finish();
      shard.reset();
    };
    const dataset::FrameSink sink = [&](const dataset::FrameRecord& r, const cv::Mat& rgb, const cv::Mat& depth) {
      if (shard && shard->bytes() >= static_cast<size_t>(shard_mib) << 20) finishShard();
      if (!shard) {
        char name[64];
        std::snprintf(name, sizeof(name), "%s-%03zu.zip", split.c_str(), shards.size());
        shards.push_back((fs::path(out) / name).string());
        shard = std::make_unique<dataset::ShardWriter>(shards.back(), meta);
      }
      shard->add(r, rgb, depth);
    };

    nlohmann::json per_map = nlohmann::json::object();
    int frames = 0, sequence = 0, in_solid_stops = 0;
    for (size_t i = 0; i < maps.size(); ++i) {
      const auto map = quake3::loadQuake3Map(maps[i], config.world.patch_level);
      const dataset::MapRenderStats s =
          dataset::renderMapDataset(*map, maps[i], config, params, seed, in_solid == "keep", sequence, sink, shuffle);
      sequence += s.sequences;
      frames += s.frames;
      in_solid_stops += s.in_solid_stops;
      per_map[maps[i]] = s.frames;
      std::cerr << "valerant_dataset: " << i + 1 << "/" << maps.size() << " " << maps[i] << ": " << s.frames
                << " frames, " << s.sequences << " sequences, " << s.in_solid_stops << " stopped in solid\n";
    }
    finishShard();
    const nlohmann::json line = {{"tool", "valerant_dataset"}, {"split", split},   {"seed", seed},
                                 {"width", config.world.width}, {"height", config.world.height},
                                 {"maps", maps},  {"frames", frames}, {"frames_per_map", per_map},
                                 {"sequences_stopped_in_solid", in_solid_stops}, {"shards", shards},
                                 {"texture_shuffle", texture_shuffle}, {"texture_pool_images", pool.images.size()}};
    std::cout << line.dump() << std::endl;
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "valerant_dataset: error: " << e.what() << std::endl;
    return 1;
  }
}
