#pragma once
// Resolves a BSP shader name to an RGB image the way the game finds one: the name
// itself as .jpg or .tga, else the first image stage ("map"/"clampMap"/"animMap")
// of the shader script of that name (scripts/*.shader), else a neutral grey
// placeholder. Images are decoded from pk3 bytes with stb_image (OpenCV has no TGA).
// The script, when there is one, also says how the game composites the surface:
// light beams, flames and glass are translucent and write no depth.
#include <opencv2/core.hpp>
#include <string>
#include <unordered_map>

#include "valerant/world/quake3/pk3_archive.h"

namespace valerant::quake3 {

enum class TextureSource { kImage, kShaderStage, kPlaceholder };

// How the game draws a shader's first stage: its blendFunc, alphaFunc and depthWrite.
struct StageRendering {
  enum class Blend { kNone, kAdd, kFilter, kAlpha };  // dst+src, dst*src, mix by alpha
  enum class AlphaTest { kNone, kGreaterThan0, kLessThan128, kAtLeast128 };
  Blend blend = Blend::kNone;
  AlphaTest alpha_test = AlphaTest::kNone;
  bool depth_write = true;  // opaque stages, and blended ones that ask for it
};

struct ResolvedTexture {
  cv::Mat rgb;    // CV_8UC3, RGB, row 0 = t 0 (as the game uploads it)
  cv::Mat alpha;  // CV_8UC1 like rgb, or empty when the image has no alpha channel
  TextureSource source = TextureSource::kPlaceholder;
  std::string image_path;  // what was loaded, "" for the placeholder
  StageRendering stage;    // opaque unless a shader script says otherwise
};

class TextureLibrary {
 public:
  explicit TextureLibrary(const Pk3FileSystem& fs);
  ResolvedTexture resolve(const std::string& shader_name) const;

  // What the scripts say about one shader.
  struct ShaderScript {
    std::string first_image;  // "" when no stage draws an image
    StageRendering stage;
  };

 private:
  const Pk3FileSystem& fs_;
  std::unordered_map<std::string, ShaderScript> scripts_;  // lower-case shader name -> script
  // False when missing or undecodable; `alpha` stays empty for images without one.
  bool decode(const std::string& path, cv::Mat& rgb, cv::Mat& alpha) const;
};

}  // namespace valerant::quake3
