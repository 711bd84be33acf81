#include "valerant/map/corrected_keyframe.h"

namespace valerant {

std::shared_ptr<const FusedKeyframe> correctedKeyframe(const FusedKeyframe& keyframe, const Similarity3& correction) {
  auto out = std::make_shared<FusedKeyframe>();
  out->id = newKeyframeId();
  out->camera_to_map = correction.applyTo(keyframe.camera_to_map);
  out->points = keyframe.points;
  for (FusedPoint& p : out->points) p.position = correction.apply(p.position.cast<double>()).cast<float>();
  return out;
}

}  // namespace valerant
