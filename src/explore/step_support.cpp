#include "valerant/explore/step_support.h"

#include <algorithm>
#include <cmath>

#include "valerant/explore/body_point_index.h"

namespace valerant {

std::vector<double> eyeSupports(const std::vector<FloorPlane>& samples) {
  std::vector<double> out;
  out.reserve(samples.size());
  if (samples.empty()) return out;
  const FloorPlane& datum = samples.front();
  for (const FloorPlane& s : samples) out.push_back(datum.normalisedHeight(s.c) - 1);
  return out;
}

double withinAStepOfTheEye(double support, double eye_support, double step_height) {
  if (!std::isfinite(eye_support)) return support;  // a degenerate datum bounds nothing
  return std::clamp(support, eye_support - step_height, eye_support + step_height);
}

std::vector<SteppedCounts> steppedBodyCounts(const std::vector<HeightedPoint>& points,
                                             const std::vector<FloorPlane>& samples, const CollisionConfig& config,
                                             const std::vector<double>& radii) {
  std::vector<SteppedCounts> out(radii.size());
  if (radii.empty()) return out;
  // Every confident point can count or carry the body, at any height (the support can
  // climb); one index for all radii, its cells from the smallest, holding the points the
  // largest reaches. A non-finite point
  // is never within the radius.
  std::vector<const HeightedPoint*> confident;
  std::vector<Eigen::Vector3d> positions;
  confident.reserve(points.size());
  positions.reserve(points.size());
  for (const auto& p : points)
    if (p.confidence >= config.min_confidence && p.position.allFinite()) {
      confident.push_back(&p);
      positions.push_back(p.position);
    }
  const BodyPointIndex index(positions, samples, *std::min_element(radii.begin(), radii.end()),
                             *std::max_element(radii.begin(), radii.end()));
  const std::vector<double> eye_supports = eyeSupports(samples);
  const bool count_over_step = config.step_count == "above_step";
  for (size_t r = 0; r < radii.size(); ++r) {
    double support = 0;
    int unfollowed = 0;  // samples in a row with the body over the eye's floor
    for (size_t i = 0; i < samples.size(); ++i) {
      const FloorPlane& s = samples[i];
      const double eye = eye_supports[i];
      support = withinAStepOfTheEye(support, eye, config.step_height);
      const double step_top = support + config.step_height, body_low = support + config.height_low,
                   body_top = support + config.height_high;
      // The paper's band over the eye's floor, for a climb the eye did not follow; only
      // counted (and the search only widened to it) when the lag is on.
      const bool eye_known = std::isfinite(eye);
      const bool eye_counted = config.climb_lag > 0 && eye_known;
      const double eye_low = eye + config.height_low, eye_top = eye + config.height_high;
      const double top = eye_counted ? std::max(body_top, eye_top) : body_top;
      int band = 0;            // the paper's count over the support
      int over_step = 0;       // ... its part over the step: the disc is blocked where > 0
      int eye_band = 0;        // ... and over the eye's floor
      double tread = support;  // the highest point within a step (the support if none)
      bool any_tread = false;
      index.forEachWithin(s, radii[r], [&](size_t k) {
        const double h = confident[k]->h;
        if (h > top) return;
        if (eye_counted && h >= eye_low && h <= eye_top) ++eye_band;
        if (h > body_top) return;
        if (h > step_top) ++over_step;
        if (h >= body_low) ++band;
        if (h <= step_top) {
          tread = any_tread ? std::max(tread, h) : h;
          any_tread = true;
        }
      });
      const bool blocked = over_step > 0;
      if (!blocked) support = withinAStepOfTheEye(tread, eye, config.step_height);
      unfollowed = eye_counted && support > eye_low ? unfollowed + 1 : 0;
      const bool not_climbed = config.climb_lag > 0 && unfollowed > config.climb_lag;
      const int blocked_count = count_over_step ? over_step : band;
      out[r].counts.push_back(not_climbed ? eye_band : blocked ? blocked_count : 0);
      out[r].support.push_back(support);
    }
  }
  return out;
}

SteppedCounts steppedBodyCounts(const std::vector<HeightedPoint>& points, const std::vector<FloorPlane>& samples,
                                const CollisionConfig& config, double radius) {
  return steppedBodyCounts(points, samples, config, std::vector<double>{radius}).front();
}

}  // namespace valerant
