#pragma once
// A fused keyframe moved by a loop closure's correction (a similarity from the SLAM
// frame to the corrected map frame): points and camera pose mapped, floor-normalised
// heights kept (a similarity moves the floor with the points, so h is unchanged). The
// copy gets a new id, so a mirror of the map (live_map.h) sees a replaced keyframe and
// rebuilds instead of keeping the old geometry.
#include <memory>

#include "valerant/geometry/similarity3.h"
#include "valerant/map/map_fusion.h"

namespace valerant {

std::shared_ptr<const FusedKeyframe> correctedKeyframe(const FusedKeyframe& keyframe, const Similarity3& correction);

}  // namespace valerant
