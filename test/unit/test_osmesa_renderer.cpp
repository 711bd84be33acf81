// The offscreen renderer: depth of known geometry, the pinhole model, cameras inside
// walls and outside the map, and texture resolution on a real map.
#include <gtest/gtest.h>

#include <cmath>

#include "openarena_data.h"
#include "valerant/world/quake3/quake3_map.h"
#include "valerant/world/quake3/camera_kinematics.h"
#include "valerant/world/quake3/osmesa_renderer.h"

using namespace valerant;
using namespace valerant::quake3;

namespace {

Eigen::Isometry3f lookingDown(const Eigen::Vector3f& eye) {
  Eigen::Isometry3f t = Eigen::Isometry3f::Identity();
  t.linear() << 0, -1, 0, -1, 0, 0, 0, 0, -1;  // x right = -Y, y down = -X, z forward = -Z
  t.translation() = eye;
  return t;
}

}  // namespace

TEST(OsMesaRenderer, DepthOfTheFloorAndPinholeGeometry) {
  VALERANT_REQUIRE_OPENARENA();
  auto map = loadQuake3Map("oa_dm1", 8);
  const CameraIntrinsics k = CameraIntrinsics::fromHorizontalFov(320, 240, 90);
  OsMesaRenderer renderer(map->bsp, map->geometry, *map->textures, k);
  const CameraKinematics kinematics(*map->collision, 50, 1024);
  const CameraState spawn = kinematics.spawn(map->bsp.spawnPoints()[0]);
  // Straight down from the eye: the floor is 50 units away at the image centre.
  const RenderedView down = renderer.render(lookingDown(kinematics.eye(spawn).cast<float>()));
  EXPECT_NEAR(down.depth.at<float>(120, 160), 50.f, 0.5f);
  // Level view from the spawn: mostly finite depth, a textured (non-flat) image.
  const RenderedView level = renderer.render(kinematics.cameraToWorld(spawn).cast<float>());
  const double finite = cv::countNonZero(level.depth == level.depth) / double(level.depth.total());
  EXPECT_GT(finite, 0.9);
  cv::Scalar mean, stddev;
  cv::meanStdDev(level.rgb, mean, stddev);
  EXPECT_GT(stddev[0], 5.0);
  // Pinhole check: the floor point under image row v lies at depth d with
  // height (v - cy) d / fy = 50 below the eye (a flat floor in front of the spawn).
  const int v = 200;
  const float d = level.depth.at<float>(v, 160);
  if (std::isfinite(d)) EXPECT_NEAR((v - k.cy) * d / k.fy, 50.0, 1.5);
}

TEST(OsMesaRenderer, InsideWallsAndOutsideTheMapIsSafe) {
  VALERANT_REQUIRE_OPENARENA();
  auto map = loadQuake3Map("oa_dm1", 8);
  OsMesaRenderer renderer(map->bsp, map->geometry, *map->textures, CameraIntrinsics::fromHorizontalFov(64, 48, 90));
  // Far outside the map: only sky colour, no depth at all.
  const RenderedView outside = renderer.render(lookingDown({1e5f, 1e5f, 1e5f}));
  EXPECT_EQ(cv::countNonZero(outside.depth == outside.depth), 0);
  // Inside a solid brush: the camera cluster is -1; the frame still renders.
  const auto& brush = map->collision->brushes().front();
  const Eigen::Vector3f inside = brush.bounds.center();
  EXPECT_LT(map->bsp.leafs[map->bsp.leafAt(inside)].cluster, 0);
  const RenderedView wall = renderer.render(lookingDown(inside));
  EXPECT_EQ(wall.rgb.size(), cv::Size(64, 48));
  EXPECT_EQ(wall.depth.type(), CV_32F);
}

TEST(OsMesaRenderer, TexturesResolveFromImagesAndShaders) {
  VALERANT_REQUIRE_OPENARENA();
  auto map = loadQuake3Map("oa_dm1", 8);
  OsMesaRenderer renderer(map->bsp, map->geometry, *map->textures, CameraIntrinsics::fromHorizontalFov(64, 48, 90));
  const TextureStats& s = renderer.textureStats();
  EXPECT_EQ(s.placeholders, 0);
  EXPECT_GT(s.images, 20);
  EXPECT_GT(s.shader_stages, 0);
  EXPECT_EQ(map->textures->resolve("textures/no/such_texture").source, TextureSource::kPlaceholder);
}
