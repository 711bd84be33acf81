#include "valerant/world/quake3/surface_samples.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "valerant/world/quake3/units.h"

namespace valerant::quake3 {
namespace {

struct Triangle {
  Eigen::Vector3f a, b, c;
  Eigen::Vector3f normal;
};

// Every drawn non-sky triangle with a non-zero area, its normal on the side its
// vertex normals point to (the BSP's winding order is not what defines the front).
std::vector<Triangle> drawnTriangles(const MapGeometry& geometry) {
  std::vector<Triangle> triangles;
  for (const DrawSurface& s : geometry.surfaces) {
    if (s.sky) continue;
    for (uint32_t k = s.first_index; k + 2 < s.first_index + s.num_indices; k += 3) {
      const BspVertex& va = geometry.vertices[geometry.indices[k]];
      const BspVertex& vb = geometry.vertices[geometry.indices[k + 1]];
      const BspVertex& vc = geometry.vertices[geometry.indices[k + 2]];
      Eigen::Vector3f n = (vb.position - va.position).cross(vc.position - va.position);
      if (n.squaredNorm() == 0) continue;
      n.normalize();
      if (n.dot(va.normal + vb.normal + vc.normal) < 0) n = -n;
      triangles.push_back({va.position, vb.position, vc.position, n});
    }
  }
  return triangles;
}

}  // namespace

std::vector<SurfaceSample> sampleSurfaces(const MapGeometry& geometry, float per_square_metre,
                                          uint32_t seed) {
  const std::vector<Triangle> triangles = drawnTriangles(geometry);
  std::vector<double> cumulative_area;  // game units^2
  cumulative_area.reserve(triangles.size());
  double total = 0;
  for (const Triangle& t : triangles) {
    total += 0.5 * static_cast<double>((t.b - t.a).cross(t.c - t.a).norm());
    cumulative_area.push_back(total);
  }
  const auto count = static_cast<size_t>(
      std::llround(total / (kUnitsPerMetre * kUnitsPerMetre) * std::max(0.f, per_square_metre)));
  std::vector<SurfaceSample> samples;
  if (count == 0) return samples;
  samples.reserve(count);

  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> where(0.0, total);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  for (size_t i = 0; i < count; ++i) {
    // Pick a triangle with probability proportional to its area, then a uniform
    // point in it (the square-root warp keeps the density flat).
    const size_t t = std::min<size_t>(
        std::upper_bound(cumulative_area.begin(), cumulative_area.end(), where(rng)) - cumulative_area.begin(),
        triangles.size() - 1);
    const Triangle& tri = triangles[t];
    const float r1 = std::sqrt(unit(rng)), r2 = unit(rng);
    const Eigen::Vector3f p = (1 - r1) * tri.a + r1 * (1 - r2) * tri.b + r1 * r2 * tri.c;
    samples.push_back({p, tri.normal});
  }
  return samples;
}

}  // namespace valerant::quake3
