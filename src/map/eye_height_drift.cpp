#include "valerant/map/eye_height_drift.h"

#include <algorithm>
#include <cmath>

#include "valerant/common/median.h"

namespace valerant {

namespace {
constexpr double kFloorBand = 0.05;    // |h| of a floor point, in eye heights
constexpr size_t kMinFloorPoints = 50;  // fewer: a keyframe that hardly saw its floor
constexpr size_t kLastKeyframes = 10;
}  // namespace

std::optional<double> keyframeEyeHeight(const FusedKeyframe& keyframe) {
  const Eigen::Vector3d up = -keyframe.camera_to_map.linear().col(1);
  const Eigen::Vector3d eye = keyframe.camera_to_map.translation();
  std::vector<double> heights;
  for (const FusedPoint& p : keyframe.points) {
    if (!(std::abs(p.h) < kFloorBand)) continue;
    heights.push_back((eye - p.position.cast<double>()).dot(up) / (1.0 - p.h));
  }
  if (heights.size() < kMinFloorPoints) return std::nullopt;
  return median(std::move(heights));
}

EyeHeightDrift eyeHeightDrift(const std::vector<std::shared_ptr<const FusedKeyframe>>& keyframes,
                              double anchor_kappa) {
  EyeHeightDrift drift;
  if (!(anchor_kappa > 0)) return drift;
  std::vector<double> ratios;
  for (const auto& keyframe : keyframes) {
    const std::optional<double> kappa = keyframeEyeHeight(*keyframe);
    if (kappa) ratios.push_back(*kappa / anchor_kappa);
  }
  if (ratios.empty()) return drift;
  drift.measured_keyframes = static_cast<int>(ratios.size());
  drift.min_ratio = *std::min_element(ratios.begin(), ratios.end());
  drift.max_ratio = *std::max_element(ratios.begin(), ratios.end());
  const size_t last = std::min(ratios.size(), kLastKeyframes);
  drift.last_ratio = median(std::vector<double>(ratios.end() - static_cast<std::ptrdiff_t>(last), ratios.end()));
  return drift;
}

}  // namespace valerant
