#pragma once
// What valerant_dataset renders on one map: camera sequences that show the views
// exploration sees, from many more places than the spawns.
//   rollout  the five paper candidates (uw, jw, lw, jq, lq) from each chosen spawn
//   rotate   a full turn in place (j or l) from a random reachable floor cell: the views
//            the visual SLAM cannot triangulate
//   walk     random key segments (w, jw, lw, j, l, a, d) from a random reachable cell
//   rotate   (wall turns) a full turn in place from a random cell within 2 m of a wall
//            (near_wall_cells.h), after the other kinds so they keep their frames
// Each sequence keeps every `every`-th frame; a frame's key string says which keys
// moved the camera since the previous kept frame, run-length coded with '+' between
// runs ("jw:3+w:5"), so the data can also train an action-conditioned world model.
#include <random>
#include <string>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/world/action_sequence.h"
#include "valerant/world/quake3/bsp.h"
#include "valerant/world/quake3/camera_kinematics.h"

namespace valerant::dataset {

struct SamplingParams {
  int spawns = 3;          // spawns whose candidate rollouts are rendered
  int rotations = 12;      // turns in place from random reachable cells
  int walks = 12;          // random walks from random reachable cells
  int wall_rotations = 0;  // turns in place from random cells near a wall
  int rollout_every = 8;   // keep every 8th rollout frame (57-97 frames: 8-13 kept)
  int rotation_every = 19; // a 90 deg turn takes horizon_frames (57) frames: 19 = 30 deg
  int walk_frames = 48;
  int walk_every = 6;
};

struct SequenceSpec {
  std::string kind;  // rollout | rotate | walk
  int spawn = -1;    // spawn index, -1 for a random cell
  quake3::CameraState start;
  ActionSequence actions;
  int every = 1;
};

// The sequences of one map, deterministic for `seed`. `floor_cells` are reachable
// floor cells (feet level, game units); `spawn_states` the cameras standing on the
// map's spawns, in spawn order.
std::vector<SequenceSpec> planSequences(const std::vector<quake3::CameraState>& spawn_states,
                                        const std::vector<Eigen::Vector3f>& floor_cells, const Config& config,
                                        const SamplingParams& params, std::mt19937_64& rng);

// The keys of one motion step in the candidates' vocabulary: yaw (j/l), pitch (i/k),
// then movement (w/s, a/d); "u" for a step that does not move.
std::string keysOf(const MotionStep& step);
// Run-length key string of steps [first, last): "jw:3+w:5".
std::string runLengthKeys(const std::vector<MotionStep>& steps, size_t first, size_t last);

// A seed for one map: the run's seed mixed with the map name (FNV-1a), stable across
// platforms and runs, so adding a map does not change another's frames.
uint64_t mapSeed(uint64_t seed, const std::string& map);

}  // namespace valerant::dataset
