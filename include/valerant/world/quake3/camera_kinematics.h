#pragma once
// How the engine world moves the camera: like a video world model, not like a game
// player. Walls never stop it (the model can walk through them; collision detection
// downstream must notice), but the eye stays at eye height over the floor below, so
// stairs, ramps and drops are followed. The floor probe is the player hull lifted by
// one step above the current floor: if that hull is free it is dropped onto the floor
// under the new position; if it is inside solid (we are walking into a wall or a
// ledge too high to step on) the floor height is kept, as a model would.
#include <Eigen/Geometry>
#include <optional>

#include "valerant/world/action_sequence.h"
#include "valerant/world/quake3/bsp.h"
#include "valerant/world/quake3/collision_model.h"
#include "valerant/world/quake3/player_hull.h"

namespace valerant::quake3 {

struct CameraState {
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();  // game units
  double floor_z = 0;                            // feet height
  double yaw_deg = 0;                            // 0 = +X, 90 = +Y
  double pitch_deg = 0;                          // positive looks down
};

class CameraKinematics {
 public:
  CameraKinematics(const CollisionModel& collision, double eye_height, double max_drop,
                   PlayerHull hull = {});

  // Standing on the floor under a spawn point. Throws InputError when it has none.
  CameraState spawn(const SpawnPoint& spawn) const;
  CameraState step(const CameraState& state, const MotionStep& motion) const;

  Eigen::Vector3d eye(const CameraState& s) const;
  // Optical frame (x right, y down, z forward) in the BSP frame.
  Eigen::Isometry3d cameraToWorld(const CameraState& s) const;
  // The pose penetrates the world: hullInSolid() or outsideWorld(). Every in-solid
  // ground-truth flag is this one.
  bool inSolid(const CameraState& s) const { return hullInSolid(s) || outsideWorld(s); }
  // The player hull at this camera overlaps solid brushes.
  bool hullInSolid(const CameraState& s) const;
  // The player hull overlaps player-clip brushes and nothing else: brushes with
  // kContentsPlayerClip but not kContentsSolid whose shader is nodraw (common/clip,
  // full_clip, ...): they stop the player, and no camera can see them. Drawn clip
  // brushes (grates, energy fields) are visible, so not clip-only.
  bool hullInClipOnly(const CameraState& s) const;
  // The centre of the player hull lies outside the playable world (a BSP leaf without a
  // cluster, or outside the world model's bounds): walked through an outer wall.
  bool outsideWorld(const CameraState& s) const;
  // Centre of the player hull's box at this camera.
  Eigen::Vector3f hullCentre(const CameraState& s) const;

 private:
  std::optional<double> floorUnder(const Eigen::Vector2d& xy, double probe_feet_z) const;
  const CollisionModel& collision_;
  double eye_height_, max_drop_;
  PlayerHull hull_;
};

}  // namespace valerant::quake3
