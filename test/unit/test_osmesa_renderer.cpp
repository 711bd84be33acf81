// The offscreen renderer on oa_dm1: a textured spawn view, depth of the floor under
// the eye, the pinhole model on a tilted and rolled view of that floor, cameras inside
// walls, outside the map and with a broken pose, and where textures come from.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "openarena_data.h"
#include "valerant/common/error.h"
#include "valerant/world/quake3/osmesa_renderer.h"

using namespace valerant;
using namespace valerant::quake3;

namespace {

// One load of oa_dm1 for every test here.
struct OaDm1 {
  Pk3FileSystem fs;
  BspMap map;
  MapGeometry geometry;
  std::unique_ptr<TextureLibrary> textures;
  OaDm1() {
    fs.mountDirectory(Pk3FileSystem::defaultDataDir());
    map = parseBsp(*fs.read("maps/oa_dm1.bsp"), "oa_dm1");
    geometry = buildMapGeometry(map, 8);
    textures = std::make_unique<TextureLibrary>(fs);
  }
};

const OaDm1& oaDm1() {
  static const OaDm1 data;
  return data;
}

const CameraIntrinsics kCamera = CameraIntrinsics::fromHorizontalFov(320, 240, 90);

// The player's eye at a spawn point: 26 units above its origin, 50 above the floor.
Eigen::Vector3f spawnEye(const SpawnPoint& s) { return s.origin + Eigen::Vector3f(0, 0, 26); }

// Optical frame for a heading (yaw, 0 = +X), pitch (down positive) and roll about the
// optical axis (clockwise in the image positive), all in degrees.
Eigen::Isometry3f cameraPose(const Eigen::Vector3f& eye, float yaw, float pitch, float roll = 0) {
  const float deg = static_cast<float>(M_PI) / 180.f;
  // Level camera looking along +X: x right = -Y, y down = -Z, z forward = +X.
  Eigen::Matrix3f level;
  level << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  const Eigen::Matrix3f r = Eigen::AngleAxisf(yaw * deg, Eigen::Vector3f::UnitZ()).toRotationMatrix() * level *
                            Eigen::AngleAxisf(-pitch * deg, Eigen::Vector3f::UnitX()).toRotationMatrix() *
                            Eigen::AngleAxisf(roll * deg, Eigen::Vector3f::UnitZ()).toRotationMatrix();
  Eigen::Isometry3f t = Eigen::Isometry3f::Identity();
  t.linear() = r;
  t.translation() = eye;
  return t;
}

double finiteFraction(const cv::Mat& depth) {
  return cv::countNonZero(depth == depth) / static_cast<double>(depth.total());
}

}  // namespace

TEST(OsMesaRenderer, SpawnViewIsTexturedWithPlausibleDepth) {
  VALERANT_REQUIRE_OPENARENA();
  const OaDm1& d = oaDm1();
  OsMesaRenderer renderer(d.map, d.geometry, *d.textures, kCamera);
  const SpawnPoint spawn = d.map.spawnPoints().at(0);
  const RenderedView view = renderer.render(cameraPose(spawnEye(spawn), spawn.yaw_deg, 0));
  ASSERT_EQ(view.rgb.type(), CV_8UC3);
  ASSERT_EQ(view.depth.type(), CV_32F);
  ASSERT_EQ(view.rgb.size(), cv::Size(320, 240));
  ASSERT_EQ(view.depth.size(), cv::Size(320, 240));
  cv::Scalar mean, stddev;
  cv::meanStdDev(view.rgb, mean, stddev);
  EXPECT_GT(stddev[0] + stddev[1] + stddev[2], 15.0) << "the image is nearly uniform";
  EXPECT_GT(mean[0] + mean[1] + mean[2], 30.0) << "the image is nearly black";
  // oa_dm1 is indoors without sky: every pixel sees a wall, floor or ceiling.
  EXPECT_GT(finiteFraction(view.depth), 0.98);
  double lo = 0, hi = 0;
  cv::minMaxIdx(view.depth, &lo, &hi, nullptr, nullptr, view.depth == view.depth);
  EXPECT_GE(lo, 4.0);  // the near plane
  EXPECT_LT(hi, 4096.0);
}

TEST(OsMesaRenderer, FloorStraightBelowTheEyeIs50UnitsAway) {
  VALERANT_REQUIRE_OPENARENA();
  const OaDm1& d = oaDm1();
  OsMesaRenderer renderer(d.map, d.geometry, *d.textures, kCamera);
  const SpawnPoint spawn = d.map.spawnPoints().at(0);
  const RenderedView down = renderer.render(cameraPose(spawnEye(spawn), spawn.yaw_deg, 90));
  // The floor is parallel to the image plane: 50 units along the optical axis everywhere
  // near the centre.
  for (int v = 110; v <= 130; v += 5)
    for (int u = 150; u <= 170; u += 5) EXPECT_NEAR(down.depth.at<float>(v, u), 50.f, 0.25f) << u << "," << v;
}

TEST(OsMesaRenderer, TiltedAndRolledFloorViewFollowsThePinholeModel) {
  VALERANT_REQUIRE_OPENARENA();
  const OaDm1& d = oaDm1();
  OsMesaRenderer renderer(d.map, d.geometry, *d.textures, kCamera);
  const SpawnPoint spawn = d.map.spawnPoints().at(0);
  const Eigen::Vector3f eye = spawnEye(spawn);
  // Pitch and roll make depth depend on both u and v: a mirrored or flipped image, a
  // principal point off by half a pixel or a focal length off by 1% break the match.
  const Eigen::Isometry3f pose = cameraPose(eye, spawn.yaw_deg, 60, 45);
  const RenderedView view = renderer.render(pose);
  int checked = 0, matched = 0;
  for (int v = 0; v < kCamera.height; v += 4) {
    for (int u = 0; u < kCamera.width; u += 4) {
      const Eigen::Vector3f ray((u - kCamera.cx) / kCamera.fx, (v - kCamera.cy) / kCamera.fy, 1.f);
      const Eigen::Vector3f world_ray = pose.linear() * ray;
      if (world_ray.z() > -0.2f) continue;
      const float depth = 50.f / -world_ray.z();  // along the optical axis, as ray.z == 1
      // Only floor points close to the spawn, which stands on flat floor.
      if ((depth * world_ray).head<2>().norm() > 40.f) continue;
      ++checked;
      matched += std::abs(view.depth.at<float>(v, u) - depth) < 0.05f;
    }
  }
  ASSERT_GT(checked, 200);
  EXPECT_GT(matched, 0.95 * checked) << matched << " of " << checked << " floor pixels at the predicted depth";
}

TEST(OsMesaRenderer, CamerasInsideSolidOutsideTheMapOrBrokenAreSafe) {
  VALERANT_REQUIRE_OPENARENA();
  const OaDm1& d = oaDm1();
  RenderOptions options;
  OsMesaRenderer renderer(d.map, d.geometry, *d.textures, kCamera, options);
  auto is_sky = [&](const RenderedView& v) {
    cv::Mat sky_pixels;
    cv::inRange(v.rgb, options.sky_rgb, options.sky_rgb, sky_pixels);
    return cv::countNonZero(sky_pixels) == static_cast<int>(v.rgb.total()) && finiteFraction(v.depth) == 0;
  };
  // Far outside the map everything is beyond the far plane: only sky.
  EXPECT_TRUE(is_sky(renderer.render(cameraPose({1e5f, 1e5f, 1e5f}, 0, 30))));
  // A non-finite pose sees nothing rather than garbage.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(is_sky(renderer.render(cameraPose({nan, 0, 0}, 0, 0))));

  // Inside solid (a leaf without cluster, within the map's bounds): no PVS row, the
  // frustum alone culls; the frame is well formed and its depth within range.
  const Eigen::AlignedBox3f& bounds = d.geometry.bounds;
  int solid_views = 0;
  for (float f = 0.05f; f < 1.f && solid_views < 5; f += 0.01f) {
    const Eigen::Vector3f p = bounds.min() + f * bounds.sizes();
    if (d.map.leafs[d.map.leafAt(p)].cluster >= 0) continue;
    ++solid_views;
    const RenderedView v = renderer.render(cameraPose(p, 360 * f, 0));
    ASSERT_EQ(v.rgb.size(), cv::Size(320, 240));
    ASSERT_EQ(v.depth.type(), CV_32F);
    double lo = 0, hi = 0;
    if (finiteFraction(v.depth) > 0) {
      cv::minMaxIdx(v.depth, &lo, &hi, nullptr, nullptr, v.depth == v.depth);
      EXPECT_GE(lo, 4.0);
      EXPECT_LE(hi, 8192.0);
    }
  }
  EXPECT_GT(solid_views, 0) << "no point inside solid found along the diagonal";
  // The renderer is still fine afterwards.
  const SpawnPoint spawn = d.map.spawnPoints().at(0);
  EXPECT_GT(finiteFraction(renderer.render(cameraPose(spawnEye(spawn), spawn.yaw_deg, 0)).depth), 0.98);
}

TEST(OsMesaRenderer, TexturesComeFromImagesAndShaderScripts) {
  VALERANT_REQUIRE_OPENARENA();
  const OaDm1& d = oaDm1();
  OsMesaRenderer renderer(d.map, d.geometry, *d.textures, CameraIntrinsics::fromHorizontalFov(64, 48, 90));
  const TextureStats& s = renderer.textureStats();
  EXPECT_GE(s.images, 20);
  EXPECT_GT(s.images, 3 * (s.shader_stages + s.placeholders));
  EXPECT_GT(s.shader_stages, 0);
  EXPECT_LE(s.placeholders, 1);
}

TEST(OsMesaRenderer, OverriddenTexturesChangeColourNotDepth) {
  VALERANT_REQUIRE_OPENARENA();
  const OaDm1& d = oaDm1();
  const CameraIntrinsics small = CameraIntrinsics::fromHorizontalFov(64, 48, 90);
  OsMesaRenderer renderer(d.map, d.geometry, *d.textures, small);
  const std::vector<int> shaders = renderer.retexturableShaders();
  ASSERT_GE(shaders.size(), 10u);
  ASSERT_TRUE(std::is_sorted(shaders.begin(), shaders.end()));
  // The light beam blends additively: its texture stays its own.
  for (int s : shaders) EXPECT_EQ(d.map.shaders[s].name.find("textures/sfx/beam"), std::string::npos);
  const SpawnPoint spawn = d.map.spawnPoints().at(0);
  const Eigen::Isometry3f pose = cameraPose(spawnEye(spawn), spawn.yaw_deg, 10);
  const RenderedView own = renderer.render(pose);

  // Every retexturable shader pure green: lit by the lightmaps, so no red or blue is left
  // where they are drawn, and the depth is the same to the bit.
  std::map<int, cv::Mat> green;
  for (int s : shaders) green[s] = cv::Mat(4, 4, CV_8UC3, cv::Scalar(0, 255, 0));
  renderer.overrideTextures(green);
  const RenderedView shuffled = renderer.render(pose);
  EXPECT_EQ(cv::norm(own.depth, shuffled.depth, cv::NORM_L1, own.depth == own.depth), 0.0);
  EXPECT_EQ(cv::countNonZero(own.depth == own.depth), cv::countNonZero(shuffled.depth == shuffled.depth));
  std::vector<cv::Mat> channels;
  cv::split(shuffled.rgb, channels);
  EXPECT_GT(cv::countNonZero(channels[1] > 20), 0.8 * shuffled.rgb.total());
  EXPECT_GT(cv::countNonZero(channels[0] == 0), 0.8 * shuffled.rgb.total());
  EXPECT_GT(cv::norm(own.rgb, shuffled.rgb, cv::NORM_L1), 10.0 * own.rgb.total());

  // One shader only, and the rest keep their own; an empty map restores every texture.
  renderer.overrideTextures({{shaders.front(), green.begin()->second}});
  renderer.overrideTextures({});
  EXPECT_EQ(cv::norm(own.rgb, renderer.render(pose).rgb, cv::NORM_L1), 0.0);
  EXPECT_THROW(renderer.overrideTextures({{shaders.front(), cv::Mat(4, 4, CV_8UC1)}}), InputError);
}

TEST(TextureLibrary, ResolvesImagesShaderStagesAndPlaceholders) {
  VALERANT_REQUIRE_OPENARENA();
  const TextureLibrary& textures = *oaDm1().textures;
  // An image named like the shader.
  const ResolvedTexture wall = textures.resolve("textures/gothic_block/blocks10");
  EXPECT_EQ(wall.source, TextureSource::kImage);
  EXPECT_EQ(wall.image_path, "textures/gothic_block/blocks10.jpg");
  EXPECT_EQ(wall.rgb.type(), CV_8UC3);
  EXPECT_EQ(wall.rgb.size(), cv::Size(512, 512));
  EXPECT_EQ(wall.stage.blend, StageRendering::Blend::kNone);
  EXPECT_TRUE(wall.stage.depth_write);
  // An extension in the name is ignored, and so is case.
  EXPECT_EQ(textures.resolve("Textures/Gothic_Block/Blocks10.tga").image_path, wall.image_path);
  // No image of that name: the first image stage of its script, which blends additively
  // (a light beam) and so writes no depth.
  const ResolvedTexture beam = textures.resolve("textures/sfx/beam_dusty2");
  EXPECT_EQ(beam.source, TextureSource::kShaderStage);
  EXPECT_EQ(beam.image_path, "textures/sfx/beam.jpg");
  EXPECT_EQ(beam.stage.blend, StageRendering::Blend::kAdd);
  EXPECT_FALSE(beam.stage.depth_write);
  // Nothing at all: a grey placeholder.
  const ResolvedTexture none = textures.resolve("textures/no/such_texture");
  EXPECT_EQ(none.source, TextureSource::kPlaceholder);
  EXPECT_TRUE(none.image_path.empty());
  EXPECT_EQ(none.rgb.type(), CV_8UC3);
  EXPECT_FALSE(none.rgb.empty());
  EXPECT_EQ(none.rgb.at<cv::Vec3b>(0, 0), cv::Vec3b(128, 128, 128));
}
