// The quick-look renderer on a map made kilometres wide by a runaway SLAM scale: the
// overview shrinks its scale to exports.overview_max_side_px instead of asking Mesa
// for a canvas past its limit (which crashed an exploration run), and a canvas past
// that limit is a named error, not a crash.
#include <gtest/gtest.h>

#include "valerant/common/error.h"
#include "valerant/map/mesh_renderer.h"

using namespace valerant;

namespace {

// A flat grey floor quad [0, x] x [0, z] at height 0, normals up.
SurfaceMesh floorQuad(float x, float z) {
  SurfaceMesh mesh;
  mesh.positions = {{0, 0, 0}, {x, 0, 0}, {x, 0, z}, {0, 0, z}};
  mesh.normals.assign(4, Eigen::Vector3f::UnitY());
  mesh.colours.assign(4, {100, 100, 100});
  mesh.heights.assign(4, 0.f);
  mesh.triangles = {{0, 2, 1}, {0, 3, 2}};
  return mesh;
}

}  // namespace

TEST(MeshRenderer, AKilometreWideMapIsDrawnAtASmallerScale) {
  ExportConfig config;  // 16 px/m, at most 4096 px a side
  const cv::Mat image = renderOverview(floorQuad(3000, 1000), WalkableArea{}, AssetNodes{}, config);
  // 16 px/m would be 48,000 x 16,000; the scale becomes 4096 / 3000 px/m:
  // 3000 m -> 4096 px, 1000 m -> ceil(1365.3) = 1366 px.
  EXPECT_EQ(image.cols, 4096);
  EXPECT_EQ(image.rows, 1366);
  // The floor fills the picture. Its shade by hand: light direction (0.3, 1, 0.5)/1.1576,
  // n.l = 0.8638, light = 0.45 + 0.55 * 0.8638 = 0.9251; the median level 100 is brought
  // toward 120, gain 1.2: 100 * 1.2 * 0.9251 = 111.
  const cv::Vec3b centre = image.at<cv::Vec3b>(image.rows / 2, image.cols / 2);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(centre[k], 111, 1);
}

TEST(MeshRenderer, ASmallMapKeepsTheConfiguredScale) {
  ExportConfig config;
  const cv::Mat image = renderOverview(floorQuad(10, 5), WalkableArea{}, AssetNodes{}, config);
  EXPECT_EQ(image.cols, 160);  // 10 m at 16 px/m
  EXPECT_EQ(image.rows, 80);
}

TEST(MeshRenderer, ACanvasPastTheRasterisersLimitIsANamedError) {
  MeshRenderer renderer(40000, 16);  // Mesa's limit is 16384 a side
  try {
    renderer.render(floorQuad(1, 1), Eigen::Matrix4f::Identity(), Eigen::Matrix4f::Identity());
    FAIL() << "rendered a 40000 px wide canvas";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("40000 x 16"), std::string::npos) << e.what();
  }
}
