#include "valerant/dataset/dataset_sequences.h"

#include "valerant/common/error.h"
#include "valerant/dataset/near_wall_cells.h"

namespace valerant::dataset {
namespace {

quake3::CameraState randomCell(const std::vector<Eigen::Vector3f>& cells, std::mt19937_64& rng) {
  const Eigen::Vector3f& c = cells[std::uniform_int_distribution<size_t>(0, cells.size() - 1)(rng)];
  quake3::CameraState s;
  s.xy = c.head<2>().cast<double>();
  s.floor_z = c.z();
  s.yaw_deg = std::uniform_real_distribution<double>(0.0, 360.0)(rng);
  return s;
}

std::string randomWalkKeys(int frames, std::mt19937_64& rng) {
  static const char* kKeys[] = {"w", "w", "jw", "lw", "j", "l", "a", "d"};
  std::uniform_int_distribution<int> key(0, 7), length(6, 18);
  std::string keys;
  for (int total = 0; total < frames;) {
    const int n = std::min(length(rng), frames - total);
    keys += (keys.empty() ? "" : ",") + std::string(kKeys[key(rng)]) + ":" + std::to_string(n);
    total += n;
  }
  return keys;
}

}  // namespace

std::vector<SequenceSpec> planSequences(const std::vector<quake3::CameraState>& spawn_states,
                                        const std::vector<Eigen::Vector3f>& floor_cells, const Config& config,
                                        const SamplingParams& params, std::mt19937_64& rng) {
  std::vector<SequenceSpec> out;
  const int spawns = std::min<int>(params.spawns, static_cast<int>(spawn_states.size()));
  for (int i = 0; i < spawns; ++i) {
    // Spread over the spawn list: maps list spawns room by room.
    const int index = static_cast<int>(static_cast<long>(i) * static_cast<long>(spawn_states.size()) / spawns);
    for (const std::string& candidate : candidateNames())
      out.push_back({"rollout", index, spawn_states[index], makeActionSequence(candidate, config),
                     params.rollout_every});
  }
  if (floor_cells.empty()) return out;
  // A full turn in place, left or right, from a random one of `cells`.
  const auto addTurn = [&](const std::vector<Eigen::Vector3f>& cells) {
    const int turn_frames = 4 * config.rollout.horizon_frames;  // four 90 deg turns
    const quake3::CameraState start = randomCell(cells, rng);
    const std::string keys = std::string(rng() % 2 ? "j:" : "l:") + std::to_string(turn_frames);
    out.push_back({"rotate", -1, start, makeActionSequence(keys, config), params.rotation_every});
  };
  for (int i = 0; i < params.rotations; ++i) addTurn(floor_cells);
  for (int i = 0; i < params.walks; ++i) {
    const quake3::CameraState start = randomCell(floor_cells, rng);
    out.push_back({"walk", -1, start, makeActionSequence(randomWalkKeys(params.walk_frames, rng), config),
                   params.walk_every});
  }
  if (params.wall_rotations > 0) {
    std::vector<Eigen::Vector3f> near_wall;
    for (size_t i : nearWallCells(floor_cells)) near_wall.push_back(floor_cells[i]);
    for (int i = 0; i < params.wall_rotations && !near_wall.empty(); ++i) addTurn(near_wall);
  }
  return out;
}

std::string keysOf(const MotionStep& s) {
  std::string k;
  if (s.yaw_deg > 0) k += 'j';
  if (s.yaw_deg < 0) k += 'l';
  if (s.pitch_deg > 0) k += 'k';
  if (s.pitch_deg < 0) k += 'i';
  if (s.forward_units > 0) k += 'w';
  if (s.forward_units < 0) k += 's';
  if (s.strafe_units > 0) k += 'd';
  if (s.strafe_units < 0) k += 'a';
  return k.empty() ? "u" : k;
}

std::string runLengthKeys(const std::vector<MotionStep>& steps, size_t first, size_t last) {
  if (first > last || last > steps.size()) throw InputError("key range", "outside the sequence");
  std::string out;
  for (size_t i = first; i < last;) {
    const std::string keys = keysOf(steps[i]);
    size_t j = i + 1;
    while (j < last && keysOf(steps[j]) == keys) ++j;
    out += (out.empty() ? "" : "+") + keys + ":" + std::to_string(j - i);
    i = j;
  }
  return out;
}

uint64_t mapSeed(uint64_t seed, const std::string& map) {
  uint64_t h = 1469598103934665603ULL;  // FNV-1a offset basis
  for (unsigned char c : map) h = (h ^ c) * 1099511628211ULL;
  return h ^ (seed * 0x9E3779B97F4A7C15ULL);
}

}  // namespace valerant::dataset
