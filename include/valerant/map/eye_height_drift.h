#pragma once
// How far the map's scale drifted, measured by the player's eye height (report.json
// `eye_height_drift`; docs/floor_in_view.md). A monocular map's scale is arbitrary and
// the visual SLAM's drifts: over 60 visual steps its metres per map unit grew 1.1 to 14
// times against the truth. Every keyframe's camera stood one eye height over its own
// floor, so that height in map units (kappa_k) measures the scale where the keyframe
// was made: kappa_k / kappa_0 is 1 for a map of one scale, 0.5 where it came out at half
// size. No ground truth is needed; on those runs kappa_k times the true metres per map
// unit stayed within 15 % of the eye's 1.5625 m.
//
// kappa_k is read off the keyframe's floor points (|h| < kFloorBand of its own floor):
// a point at normalised height h lies kappa_k (1 - h) under the camera along the floor's
// normal, taken here as the camera's up (-y of the optical frame; the player's eye looks
// level as it walks).
#include <optional>
#include <vector>

#include "valerant/map/map_fusion.h"

namespace valerant {

struct EyeHeightDrift {
  int measured_keyframes = 0;  // keyframes with enough floor points
  // kappa_k / kappa_0 over the measured keyframes, and over the last ones measured
  // (the median of the latest kLastKeyframes): 1 for a map of one scale. 0 when none.
  double min_ratio = 0, max_ratio = 0, last_ratio = 0;
};

// kappa of one keyframe in map units: the median over its floor points of their depth
// under the camera along its up divided by (1 - h); nullopt with fewer than
// kMinFloorPoints such points.
std::optional<double> keyframeEyeHeight(const FusedKeyframe& keyframe);

// Every keyframe's kappa against `anchor_kappa` (kappa_0, Episode::anchorEyeHeight; an
// empty result when it is not positive).
EyeHeightDrift eyeHeightDrift(const std::vector<std::shared_ptr<const FusedKeyframe>>& keyframes,
                              double anchor_kappa);

}  // namespace valerant
