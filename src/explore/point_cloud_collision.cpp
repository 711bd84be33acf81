#include "valerant/explore/point_cloud_collision.h"

#include "valerant/explore/body_point_index.h"
#include "valerant/explore/step_support.h"

namespace valerant {

std::vector<int> bodyCylinderCounts(const std::vector<HeightedPoint>& points, const std::vector<FloorPlane>& samples,
                                    const CollisionConfig& config, double radius) {
  if (config.step_height > 0) return steppedBodyCounts(points, samples, config, radius).counts;
  // Only body-level, confident points can ever count; filter them once. A point with a
  // non-finite coordinate is never within the radius.
  std::vector<Eigen::Vector3d> body;
  for (const auto& p : points)
    if (p.confidence >= config.min_confidence && p.h >= config.height_low && p.h <= config.height_high &&
        p.position.allFinite())
      body.push_back(p.position);
  const BodyPointIndex index(body, samples, radius);
  std::vector<int> counts;
  for (const FloorPlane& s : samples) counts.push_back(index.count(s, radius));
  return counts;
}

PointCloudCollision detectPointCloudCollision(const std::vector<HeightedPoint>& points,
                                              const std::vector<FloorPlane>& samples,
                                              const CollisionConfig& config, bool rotation_only) {
  PointCloudCollision result;
  const std::vector<int> counts = bodyCylinderCounts(points, samples, config, config.body_radius);
  int run = 0;  // consecutive samples at or above N_occ
  for (size_t i = 0; i < counts.size(); ++i) {
    const int count = counts[i];
    result.occupied_max = std::max(result.occupied_max, count);
    run = count >= config.n_occ ? run + 1 : 0;
    const bool sustained = run >= config.n_occ_consecutive;
    const bool deep = count >= config.n_occ_immediate;
    if (!rotation_only && !result.collision && (sustained || deep)) {
      result.collision = true;
      result.sample = static_cast<int>(i);
      result.run_start = static_cast<int>(i) - (deep ? 0 : run - 1);
    }
  }
  return result;
}

}  // namespace valerant
