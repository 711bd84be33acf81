#include "valerant/explore/step_support.h"

#include <algorithm>

namespace valerant {

SteppedCounts steppedBodyCounts(const std::vector<HeightedPoint>& points, const std::vector<FloorPlane>& samples,
                                const CollisionConfig& config, double radius) {
  std::vector<const HeightedPoint*> confident;
  for (const auto& p : points)
    if (p.confidence >= config.min_confidence) confident.push_back(&p);
  SteppedCounts out;
  double support = 0;
  for (const FloorPlane& s : samples) {
    const double kappa = s.cameraHeight();
    const double step_top = support + config.step_height, body_low = support + config.height_low,
                 body_top = support + config.height_high;
    bool blocked = false;
    int band = 0;            // the paper's count over the support
    double tread = support;  // the highest point within a step (the support if none)
    bool any_tread = false;
    if (kappa > 0) {
      const double radius2 = (radius * kappa) * (radius * kappa);
      for (const HeightedPoint* p : confident) {
        if (p->h > body_top || s.axisDistanceSquared(p->position) > radius2) continue;
        if (p->h > step_top) blocked = true;
        if (p->h >= body_low) ++band;
        if (p->h <= step_top) {
          tread = any_tread ? std::max(tread, p->h) : p->h;
          any_tread = true;
        }
      }
    }
    if (!blocked) support = tread;
    out.counts.push_back(blocked ? band : 0);
    out.support.push_back(support);
  }
  return out;
}

}  // namespace valerant
