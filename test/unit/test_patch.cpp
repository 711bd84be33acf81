// Bezier patch tessellation against hand-computed values.
#include <gtest/gtest.h>

#include "valerant/common/error.h"
#include "valerant/world/quake3/patch.h"

using namespace valerant;
using namespace valerant::quake3;

namespace {

// width x height control points on the z = 0 plane, spaced 10 units, with
// an optional height for the centre control point of every 3x3 block.
std::vector<BspVertex> grid(int width, int height, float centre_z = 0.f) {
  std::vector<BspVertex> control;
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      BspVertex v;
      v.position = {10.f * c, 10.f * r, (r % 2 == 1 && c % 2 == 1) ? centre_z : 0.f};
      v.texcoord = {static_cast<float>(c), static_cast<float>(r)};
      v.lmcoord = {0, 0};
      v.normal = {0, 0, 1};
      control.push_back(v);
    }
  }
  return control;
}

}  // namespace

TEST(Patch, FlatPatchCountsAndPlanarity) {
  const TriangleMesh mesh = tessellatePatch(grid(3, 3), 3, 3, 4);
  EXPECT_EQ(mesh.vertices.size(), 25u);       // (4+1)^2
  EXPECT_EQ(mesh.indices.size(), 4u * 4 * 6);  // 16 quads, 2 triangles each
  for (const auto& v : mesh.vertices) {
    EXPECT_FLOAT_EQ(v.position.z(), 0.f);
    EXPECT_GE(v.position.x(), 0.f);
    EXPECT_LE(v.position.x(), 20.f);
  }
  // Corners interpolate the corner control points exactly.
  EXPECT_EQ(mesh.vertices.front().position, Eigen::Vector3f(0, 0, 0));
  EXPECT_EQ(mesh.vertices.back().position, Eigen::Vector3f(20, 20, 0));
}

TEST(Patch, CurvedCentreMatchesBernsteinWeights) {
  // Centre control point at z = 8: the surface centre is (2 * 0.5 * 0.5)^2 * 8 = 2.
  const TriangleMesh mesh = tessellatePatch(grid(3, 3, 8.f), 3, 3, 2);
  ASSERT_EQ(mesh.vertices.size(), 9u);
  EXPECT_NEAR(mesh.vertices[4].position.z(), 2.f, 1e-5);
  EXPECT_NEAR(mesh.vertices[4].position.x(), 10.f, 1e-5);
  // Edge midpoint: only the edge's own control row counts: 2*0.5*0.5 * 0 = 0.
  EXPECT_NEAR(mesh.vertices[1].position.z(), 0.f, 1e-5);
}

TEST(Patch, MultiBlockPatchSharesBorders) {
  const TriangleMesh mesh = tessellatePatch(grid(5, 3), 5, 3, 3);
  EXPECT_EQ(mesh.vertices.size(), 7u * 4);  // 2 blocks x 3 + 1 columns, 3 + 1 rows
  EXPECT_NEAR(mesh.vertices[3].position.x(), 20.f, 1e-5);  // shared border column
}

TEST(Patch, BadSizesAreErrors) {
  EXPECT_THROW(tessellatePatch(grid(3, 3), 4, 3, 2), InputError);  // even width
  EXPECT_THROW(tessellatePatch(grid(3, 3), 5, 3, 2), InputError);  // wrong count
  EXPECT_THROW(tessellatePatch(grid(3, 3), 3, 3, 0), InputError);  // level 0
}
