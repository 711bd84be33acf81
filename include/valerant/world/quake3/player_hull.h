#pragma once
// Quake III player dimensions (bg_public.h / g_client.c), in game units.
#include <Eigen/Core>

namespace valerant::quake3 {

struct PlayerHull {
  // Bounding box around the player origin: 30 x 30 x 56 units, origin 24 above the feet.
  Eigen::Vector3f mins{-15.f, -15.f, -24.f};
  Eigen::Vector3f maxs{15.f, 15.f, 32.f};
  float eye_above_origin = 26.f;  // DEFAULT_VIEWHEIGHT
  float step_height = 18.f;       // STEPSIZE: higher ledges need a jump
  float feet_to_eye() const { return -mins.z() + eye_above_origin; }  // 50
};

}  // namespace valerant::quake3
