#include "valerant/dataset/dataset_render.h"

#include "valerant/common/error.h"
#include "valerant/world/quake3/osmesa_renderer.h"
#include "valerant/world/quake3/reachable_floor.h"
#include "valerant/world/quake3/units.h"

namespace valerant::dataset {

MapRenderStats renderMapDataset(const quake3::Quake3Map& map, const std::string& map_name, const Config& config,
                                const SamplingParams& params, uint64_t seed, bool keep_in_solid, int first_sequence,
                                const FrameSink& sink, const TextureShuffle& shuffle) {
  const WorldConfig& w = config.world;
  quake3::CameraKinematics kinematics(*map.collision, w.eye_height_units, w.max_drop_units);
  std::vector<quake3::CameraState> spawns;
  std::vector<Eigen::Vector3f> cells;
  for (const quake3::SpawnPoint& spawn : map.bsp.spawnPoints()) {
    try {
      spawns.push_back(kinematics.spawn(spawn));
      // The floor walkable from the first usable spawn: deathmatch levels are one piece.
      if (cells.empty()) cells = quake3::floodFillReachableFloor(*map.collision, spawn.origin).cells;
    } catch (const InputError&) {
      // A spawn in solid or over the void: the game would not use it either.
    }
  }
  if (spawns.empty()) throw InputError("map '" + map_name + "'", "has no spawn point with a floor under it");

  std::mt19937_64 rng(mapSeed(seed, map_name));
  const std::vector<SequenceSpec> plan = planSequences(spawns, cells, config, params, rng);
  quake3::RenderOptions options;
  options.near_plane = static_cast<float>(w.near_plane_units);
  options.far_plane = static_cast<float>(w.far_plane_units);
  quake3::OsMesaRenderer renderer(map.bsp, map.geometry, *map.textures,
                                  CameraIntrinsics::fromHorizontalFov(w.width, w.height, w.fov_x_deg), options);
  const std::vector<int> retexturable = shuffle.enabled() ? renderer.retexturableShaders() : std::vector<int>();
  MapRenderStats stats;
  for (size_t s = 0; s < plan.size(); ++s) {
    const SequenceSpec& spec = plan[s];
    if (shuffle.enabled()) {
      std::mt19937_64 texture_rng(mapSeed(seed, map_name) ^ (0xD1B54A32D192ED03ULL * (s + 1)));
      renderer.overrideTextures(shuffleTextures(retexturable, shuffle, texture_rng));
    }
    const std::vector<MotionStep>& steps = spec.actions.steps;
    quake3::CameraState camera = spec.start;
    size_t last_kept = 0;
    for (size_t i = 0; i <= steps.size(); ++i) {
      if (i > 0) camera = kinematics.step(camera, steps[i - 1]);
      const bool in_solid = kinematics.inSolid(camera);
      if (in_solid && !keep_in_solid) {
        ++stats.in_solid_stops;
        break;
      }
      if (i % spec.every != 0) continue;
      const Eigen::Isometry3d pose = kinematics.cameraToWorld(camera);
      const quake3::RenderedView view = renderer.render(pose.cast<float>());
      FrameRecord r;
      r.map = map_name;
      r.spawn = spec.spawn;
      r.sequence = first_sequence + static_cast<int>(s);
      r.step = static_cast<int>(i);
      r.kind = spec.kind;
      r.key = runLengthKeys(steps, last_kept, i);
      r.eye_m = kinematics.eye(camera) / quake3::kUnitsPerMetre;
      r.yaw_deg = camera.yaw_deg;
      r.pitch_deg = camera.pitch_deg;
      r.in_solid = in_solid;
      sink(r, view.rgb, view.depth / quake3::kUnitsPerMetre);
      last_kept = i;
      ++stats.frames;
    }
    ++stats.sequences;
  }
  return stats;
}

}  // namespace valerant::dataset
