#pragma once
// Offscreen OpenGL renderer of a Quake III map through OSMesa (Mesa's software
// rasteriser; no X display needed). Textured and lightmapped like the game's
// default shader stage (texture x lightmap, lightmaps brightened by the game's
// overbright shift); faces without lightmap use vertex colours; sky is a flat
// colour. Culls by the BSP's PVS and per-leaf frustum test before drawing.
//
// One renderer owns one OSMesa context and must be used from one thread at a time.
#include <Eigen/Geometry>
#include <map>
#include <memory>
#include <vector>
#include <opencv2/core.hpp>

#include "valerant/common/camera.h"
#include "valerant/world/quake3/bsp.h"
#include "valerant/world/quake3/map_geometry.h"
#include "valerant/world/quake3/texture_library.h"

namespace valerant::quake3 {

struct RenderOptions {
  float near_plane = 4.f;     // game units
  float far_plane = 8192.f;   // game units
  cv::Vec3b sky_rgb{110, 140, 190};
  bool use_pvs = true;
};

struct RenderedView {
  cv::Mat rgb;    // CV_8UC3, RGB
  cv::Mat depth;  // CV_32F, game units along the optical axis; NaN where only sky
};

struct TextureStats {
  int images = 0, shader_stages = 0, placeholders = 0;
};

class OsMesaRenderer {
 public:
  OsMesaRenderer(const BspMap& map, const MapGeometry& geometry, const TextureLibrary& textures,
                 const CameraIntrinsics& intrinsics, const RenderOptions& options = {});
  ~OsMesaRenderer();
  OsMesaRenderer(const OsMesaRenderer&) = delete;
  OsMesaRenderer& operator=(const OsMesaRenderer&) = delete;

  // `camera_to_world`: optical frame (x right, y down, z forward) in the BSP frame.
  RenderedView render(const Eigen::Isometry3f& camera_to_world);
  const TextureStats& textureStats() const { return stats_; }

  // Domain randomisation (valerant_dataset --texture-shuffle): the shaders whose
  // surfaces are drawn opaque without alpha test, so another image changes only their
  // appearance, never which pixels they cover or the depth; sorted BSP shader indices.
  std::vector<int> retexturableShaders() const;
  // Until the next call, draws every retexturable shader listed with its image (CV_8UC3
  // RGB, any size; rounded down to powers of two) instead of its own, still lit by its
  // lightmap or vertex colours; other shaders keep their own. An empty map restores all.
  void overrideTextures(const std::map<int, cv::Mat>& rgb_by_shader);
  const CameraIntrinsics& intrinsics() const { return intrinsics_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  CameraIntrinsics intrinsics_;
  TextureStats stats_;
};

}  // namespace valerant::quake3
