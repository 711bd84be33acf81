#include "valerant/explore/point_cloud_collision.h"

#include "valerant/explore/body_point_index.h"
#include "valerant/explore/step_support.h"

#include <algorithm>

namespace valerant {

std::vector<std::vector<int>> bodyCylinderCounts(const std::vector<HeightedPoint>& points,
                                                 const std::vector<FloorPlane>& samples,
                                                 const CollisionConfig& config, const std::vector<double>& radii) {
  std::vector<std::vector<int>> counts;
  if (config.step_height > 0) {
    for (SteppedCounts& s : steppedBodyCounts(points, samples, config, radii)) counts.push_back(std::move(s.counts));
    return counts;
  }
  if (radii.empty()) return counts;
  // Only body-level, confident points can ever count; filter them once. A point with a
  // non-finite coordinate is never within the radius.
  std::vector<Eigen::Vector3d> body;
  body.reserve(points.size());
  for (const auto& p : points)
    if (countedInBody(p.h, p.confidence, config) && p.position.allFinite())
      body.push_back(p.position);
  // The cell size from the smallest radius: a larger one only searches a wider box; the
  // points no sample reaches at the largest are left out.
  const BodyPointIndex index(body, samples, *std::min_element(radii.begin(), radii.end()),
                             *std::max_element(radii.begin(), radii.end()));
  for (double radius : radii) {
    std::vector<int>& at_radius = counts.emplace_back();
    at_radius.reserve(samples.size());
    for (const FloorPlane& s : samples) at_radius.push_back(index.count(s, radius));
  }
  return counts;
}

PointCloudCollision detectPointCloudCollision(const std::vector<HeightedPoint>& points,
                                              const std::vector<FloorPlane>& samples,
                                              const CollisionConfig& config, bool rotation_only) {
  return pointCloudCollisionFromCounts(bodyCylinderCounts(points, samples, config, {config.body_radius}).front(),
                                       config, rotation_only);
}

PointCloudCollision pointCloudCollisionFromCounts(const std::vector<int>& counts, const CollisionConfig& config,
                                                  bool rotation_only) {
  PointCloudCollision result;
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
