#pragma once
// Ground-truth figures of one episode on the engine world (never fed back to the
// pipeline): penetrations of the committed frames, the share of the reachable floor
// the fused map observed, and how the collision verdicts agree with the in-solid truth.
//
// The SLAM map is tied to the BSP frame by a Sim(3) fitted (Umeyama) between the
// committed camera centres and their ground-truth centres; floor points of the map
// (|h| < eta_low) then mark 1 m cells. A reachable 1 m cell counts as observed when a
// floor point falls in it within half a step height of a reachable floor height there.
#include <Eigen/Geometry>

#include "valerant/explore/episode.h"
#include "valerant/world/quake3/reachable_floor.h"

namespace valerant {

struct EpisodeTruth {
  int committed_frames = 0;
  int penetrating_frames = 0;  // committed frames whose player hull is inside solid
  double reachable_m2 = 0;
  double observed_reachable_m2 = 0;
  double observed_reachable_percent = 0;
  bool aligned = false;          // false: the trajectory was too short to fit a Sim(3)
  double alignment_scale = 0;    // metres per map unit
  double alignment_rmse_m = 0;   // residual of the camera centres after alignment
  int verdicts = 0;              // candidate evaluations with ground truth
  int truly_colliding = 0;       // candidates whose frames enter solid
  int predicted_colliding = 0;   // candidates rejected by a collision test
  int false_rejections = 0;      // predicted but not truly colliding
  int missed_collisions = 0;     // truly colliding but not predicted
};

// Sim(3) taking map-frame points to the BSP frame in metres, from matched centres.
// Returns false when the centres span too little to fix rotation and scale.
bool alignTrajectory(const std::vector<Eigen::Vector3d>& map_centres, const std::vector<Eigen::Vector3d>& truth_centres,
                     Eigen::Matrix4d& map_to_world);

EpisodeTruth evaluateEpisodeTruth(const Episode& episode, const quake3::ReachableFloor& reachable);

}  // namespace valerant
