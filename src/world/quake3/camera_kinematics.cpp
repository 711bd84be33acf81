#include "valerant/world/quake3/camera_kinematics.h"

#include <algorithm>
#include <cmath>

#include "valerant/common/error.h"

namespace valerant::quake3 {
namespace {
constexpr double kDegToRad = M_PI / 180.0;
constexpr double kMaxPitchDeg = 85.0;  // never look straight up or down: yaw stays defined

// The player origin of a camera: hull.mins.z() below it are the feet.
Eigen::Vector3f playerOrigin(const CameraState& s, const PlayerHull& hull) {
  return {static_cast<float>(s.xy.x()), static_cast<float>(s.xy.y()), static_cast<float>(s.floor_z - hull.mins.z())};
}
}  // namespace

CameraKinematics::CameraKinematics(const CollisionModel& collision, double eye_height,
                                   double max_drop, PlayerHull hull)
    : collision_(collision), eye_height_(eye_height), max_drop_(max_drop), hull_(hull) {}

std::optional<double> CameraKinematics::floorUnder(const Eigen::Vector2d& xy,
                                                   double probe_feet_z) const {
  const Eigen::Vector3f origin(static_cast<float>(xy.x()), static_cast<float>(xy.y()),
                               static_cast<float>(probe_feet_z - hull_.mins.z()));
  const auto rest = collision_.dropBox(origin, hull_.mins, hull_.maxs,
                                       static_cast<float>(max_drop_ + hull_.step_height));
  if (!rest) return std::nullopt;
  return *rest + hull_.mins.z();
}

CameraState CameraKinematics::spawn(const SpawnPoint& spawn) const {
  CameraState s;
  s.xy = spawn.origin.head<2>().cast<double>();
  s.yaw_deg = spawn.yaw_deg;
  // Spawn origins float a little above the floor; drop from one step above the feet.
  const double feet = spawn.origin.z() + hull_.mins.z();
  const auto floor = floorUnder(s.xy, feet + hull_.step_height);
  if (!floor) {
    throw InputError("spawn at (" + std::to_string(spawn.origin.x()) + ", " +
                         std::to_string(spawn.origin.y()) + ", " +
                         std::to_string(spawn.origin.z()) + ")",
                     "no floor under the spawn point, or the spawn is inside solid");
  }
  s.floor_z = *floor;
  return s;
}

CameraState CameraKinematics::step(const CameraState& state, const MotionStep& motion) const {
  CameraState next = state;
  next.yaw_deg = std::fmod(state.yaw_deg + motion.yaw_deg, 360.0);
  next.pitch_deg = std::clamp(state.pitch_deg + motion.pitch_deg, -kMaxPitchDeg, kMaxPitchDeg);
  // Translate along the heading the step ends with, like holding a key while turning.
  const double yaw = next.yaw_deg * kDegToRad;
  const Eigen::Vector2d forward(std::cos(yaw), std::sin(yaw));
  const Eigen::Vector2d right(std::sin(yaw), -std::cos(yaw));
  next.xy = state.xy + motion.forward_units * forward + motion.strafe_units * right;
  if (next.xy != state.xy) {
    if (const auto floor = floorUnder(next.xy, state.floor_z + hull_.step_height)) next.floor_z = *floor;
  }
  return next;
}

Eigen::Vector3d CameraKinematics::eye(const CameraState& s) const {
  return {s.xy.x(), s.xy.y(), s.floor_z + eye_height_};
}

Eigen::Isometry3d CameraKinematics::cameraToWorld(const CameraState& s) const {
  const double yaw = s.yaw_deg * kDegToRad, pitch = s.pitch_deg * kDegToRad;
  const Eigen::Vector3d forward(std::cos(yaw) * std::cos(pitch), std::sin(yaw) * std::cos(pitch),
                                -std::sin(pitch));
  const Eigen::Vector3d right(std::sin(yaw), -std::cos(yaw), 0.0);
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear().col(0) = right;
  t.linear().col(1) = down;
  t.linear().col(2) = forward;
  t.translation() = eye(s);
  return t;
}

bool CameraKinematics::hullInSolid(const CameraState& s) const {
  return collision_.boxInSolid(playerOrigin(s, hull_), hull_.mins, hull_.maxs);
}

bool CameraKinematics::hullInClipOnly(const CameraState& s) const {
  const BoxOverlap o = collision_.boxOverlap(playerOrigin(s, hull_), hull_.mins, hull_.maxs);
  return (o.contents & kContentsPlayerClip) && !(o.contents & kContentsSolid) && !o.drawn;
}

Eigen::Vector3f CameraKinematics::hullCentre(const CameraState& s) const {
  return playerOrigin(s, hull_) + (hull_.mins + hull_.maxs) / 2;
}

bool CameraKinematics::outsideWorld(const CameraState& s) const { return collision_.pointOutsideWorld(hullCentre(s)); }

}  // namespace valerant::quake3
