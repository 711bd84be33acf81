#pragma once
// Ground truth: points sampled uniformly by area on every drawn, non-sky map
// surface, with the surface normal, for map accuracy / completeness metrics.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "valerant/world/quake3/map_geometry.h"

namespace valerant::quake3 {

struct SurfaceSample {
  Eigen::Vector3f position;  // game units
  Eigen::Vector3f normal;
};

// About `per_square_metre` samples per m^2 (32 units = 1 m); deterministic for a seed.
std::vector<SurfaceSample> sampleSurfaces(const MapGeometry& geometry, float per_square_metre,
                                          uint32_t seed);

}  // namespace valerant::quake3
