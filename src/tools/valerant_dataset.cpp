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
//                    [--walks 12] [--wall-rotations 0] [--walk-frames 48] [--every N] [--shard-mib 24]
//                    [--in-solid skip|keep] [--config FILE]
//                    [--set key=value ...] [--texture-shuffle P]
//   valerant_dataset --list-maps [--split ...] [--maps ...] [--exclude ...]   (the maps, one a line)
//   (--help: every flag)
//
// --width and --height set world.width and world.height (the depth prior's input size,
// not the explorer's frame), so the configuration's checks apply to them.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "command_line.h"
#include "package_file_flag.h"
#include "tool_config.h"
#include "valerant/dataset/dataset_render.h"
#include "valerant/dataset/map_sets.h"
#include "valerant/world/quake3/units.h"

using namespace valerant;
namespace fs = std::filesystem;

namespace {

// The maps to render: --maps (or the split's maps) less --exclude; each must belong to
// the split.
std::vector<std::string> chooseMaps(const CLI::Option& maps_flag, const std::string& maps_text,
                                    const CLI::Option& exclude_flag, const std::string& exclude_text,
                                    const dataset::MapSets& sets, const std::string& split) {
  std::vector<std::string> maps;
  if (maps_flag.count()) {
    maps = tools::commaList("--maps", maps_text);
  } else if (split == "evaluation") {
    maps = sets.evaluation;
  } else {
    for (const auto& m : quake3::installedMapNames())
      if (!sets.isHeldOut(m)) maps.push_back(m);
  }
  if (exclude_flag.count()) {
    const auto exclude = tools::commaList("--exclude", exclude_text);
    maps.erase(std::remove_if(maps.begin(), maps.end(),
                              [&](const std::string& m) { return std::count(exclude.begin(), exclude.end(), m) > 0; }),
               maps.end());
  }
  for (const auto& m : maps) {
    if (split == "train" && sets.isHeldOut(m))
      throw tools::UsageError("--maps " + m,
                              "is held out for evaluation (config/map_sets.yaml): never in a training shard");
    if (split == "evaluation" && !sets.isHeldOut(m))
      throw tools::UsageError("--maps " + m, "is not a held-out map; an evaluation shard holds only those");
  }
  if (maps.empty()) throw tools::UsageError("--maps", "no map left to render");
  return maps;
}

// The check of a probability flag: a number from 0 to 1 (not NaN).
CLI::Validator probability() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        char* end = nullptr;
        const double p = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !(p >= 0.0 && p <= 1.0)) return text + " is not a probability from 0 to 1";
        return "";
      },
      "");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Renders training data for the learned parts from the engine: colour frames, true depth, poses, "
      "keys and in-solid flags along candidate rollouts, turns in place and random walks, as shards.",
      "valerant_dataset"};
  tools::useToolConventions(app);
  tools::ToolConfig tool_config(app);
  tool_config.keyFlag("--width", "world.width", "INT", "frame width in pixels", "128");
  tool_config.keyFlag("--height", "world.height", "INT", "frame height in pixels", "96");
  std::string out, split = "train", maps_text, exclude_text, in_solid = "skip";
  int64_t seed_flag = 0;
  int shard_mib = 24;
  double texture_shuffle = 0;
  dataset::SamplingParams params;
  tools::addPath(app, "--out", out, "shard folder (required unless --list-maps)", "DIR");
  app.add_option("--split", split, "train: every installed map but the held-out ones; evaluation: the held-out maps")
      ->capture_default_str()
      ->check(CLI::IsMember({"train", "evaluation"}));
  const CLI::Option* maps_flag =
      app.add_option("--maps", maps_text, "maps, comma-separated (default: the split's maps)")->type_name("LIST");
  const CLI::Option* exclude_flag =
      app.add_option("--exclude", exclude_text, "maps to leave out, comma-separated")->type_name("LIST");
  const tools::PackageFileFlag map_sets_file(app, "--map-sets", "the held-out map sets",
                                             dataset::defaultMapSetsPath, "config/map_sets.yaml");
  tools::addInteger<int64_t>(app, "--seed", seed_flag, "random seed of the sequences (and the texture shuffle)", 0);
  tools::addInteger(app, "--spawns", params.spawns, "spawns whose candidate rollouts are rendered, per map", 0);
  tools::addInteger(app, "--rotations", params.rotations, "turns in place from random reachable cells, per map", 0);
  tools::addInteger(app, "--walks", params.walks, "random walks from random reachable cells, per map", 0);
  tools::addInteger(app, "--wall-rotations", params.wall_rotations,
                    "turns in place from random reachable cells within 2 m of a wall, per map", 0);
  tools::addInteger(app, "--walk-frames", params.walk_frames, "frames of one random walk", 1);
  int every = 0;
  tools::addInteger(app, "--every", every,
                    "keep every Nth frame of every sequence (1: consecutive frames, for a world model; "
                    "0: each kind's own stride)",
                    0);
  tools::addInteger(app, "--shard-mib", shard_mib, "shard size in MiB (1 to 60)", 1, 60);
  app.add_option("--in-solid", in_solid, "skip: a sequence stops where the camera enters solid; keep: it goes on")
      ->capture_default_str()
      ->check(CLI::IsMember({"skip", "keep"}));
  app.add_option("--texture-shuffle", texture_shuffle,
                 "domain randomisation (training split only): the probability that a surface wears another image")
      ->capture_default_str()
      ->check(probability());
  const CLI::Option* list_maps = app.add_flag("--list-maps", "print the maps, one a line, and render nothing");
  return tools::runTool(app, argc, argv, [&] {
    const Config config = tool_config.document().parse();
    if (every > 0) params.rollout_every = params.rotation_every = params.walk_every = every;
    const dataset::MapSets sets = dataset::loadMapSets(map_sets_file.path());
    const std::vector<std::string> maps = chooseMaps(*maps_flag, maps_text, *exclude_flag, exclude_text, sets, split);
    if (list_maps->count()) {
      for (const auto& m : maps) std::cout << m << '\n';
      return 0;
    }
    const uint64_t seed = static_cast<uint64_t>(seed_flag);
    if (texture_shuffle > 0 && split != "train")
      throw tools::UsageError("--texture-shuffle",
                              "randomises training data only; an evaluation shard shows the maps as they are");
    if (out.empty()) throw tools::UsageError("--out", "is required");
    // Zero sequences of every kind would write no shard and still report success.
    if (params.spawns == 0 && params.rotations == 0 && params.walks == 0 && params.wall_rotations == 0)
      throw tools::UsageError("--spawns 0 --rotations 0 --walks 0 --wall-rotations 0",
                              "render nothing: give one of them a count");
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
                                 {"texture_shuffle", texture_shuffle}, {"texture_pool_images", pool.images.size()},
                                 {"every", every}, {"walk_frames", params.walk_frames}};
    std::cout << line.dump() << std::endl;
    return 0;
  });
}
