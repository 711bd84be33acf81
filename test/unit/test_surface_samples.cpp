#include <gtest/gtest.h>

#include "valerant/world/quake3/surface_samples.h"

namespace valerant::quake3 {
namespace {

using Eigen::Vector3f;

// A 64 x 64 square (4 m^2) at z = 10 facing up, wound so that the winding alone
// would give a downward normal; a sky square and an undrawn surface beside it.
MapGeometry squareWithSky() {
  MapGeometry g;
  auto vertex = [](float x, float y, float z) {
    BspVertex v;
    v.position = {x, y, z};
    v.texcoord = v.lmcoord = Eigen::Vector2f::Zero();
    v.normal = {0, 0, 1};
    return v;
  };
  g.vertices = {vertex(0, 0, 10), vertex(64, 0, 10), vertex(64, 64, 10), vertex(0, 64, 10),
                vertex(0, 0, 500), vertex(640, 0, 500), vertex(640, 640, 500)};
  g.indices = {0, 2, 1, 0, 3, 2, 4, 6, 5};
  DrawSurface square;
  square.first_index = 0;
  square.num_indices = 6;
  DrawSurface sky;
  sky.first_index = 6;
  sky.num_indices = 3;
  sky.sky = true;
  DrawSurface undrawn;
  undrawn.first_index = 9;
  g.surfaces = {square, sky, undrawn};
  return g;
}

TEST(SurfaceSamples, UniformOnTheSquareWithItsNormal) {
  const auto samples = sampleSurfaces(squareWithSky(), 100, 7);
  EXPECT_NEAR(static_cast<double>(samples.size()), 400, 1);
  int left = 0;
  for (const auto& s : samples) {
    EXPECT_GE(s.position.x(), 0);
    EXPECT_LE(s.position.x(), 64);
    EXPECT_GE(s.position.y(), 0);
    EXPECT_LE(s.position.y(), 64);
    EXPECT_NEAR(s.position.z(), 10, 1e-4);
    EXPECT_TRUE(s.normal.isApprox(Vector3f(0, 0, 1))) << s.normal.transpose();
    left += s.position.x() < 32;
  }
  // Both halves (and both triangles) get their share: 200 +- 4 sigma.
  EXPECT_NEAR(left, 200, 40);
}

TEST(SurfaceSamples, DeterministicPerSeed) {
  const MapGeometry g = squareWithSky();
  const auto a = sampleSurfaces(g, 10, 1), b = sampleSurfaces(g, 10, 1), c = sampleSurfaces(g, 10, 2);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.size(), c.size());
  bool differ = false;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].position, b[i].position);
    differ |= a[i].position != c[i].position;
  }
  EXPECT_TRUE(differ);
}

TEST(SurfaceSamples, NothingToSample) {
  EXPECT_TRUE(sampleSurfaces(MapGeometry{}, 100, 1).empty());
  EXPECT_TRUE(sampleSurfaces(squareWithSky(), 0, 1).empty());
}

}  // namespace
}  // namespace valerant::quake3
