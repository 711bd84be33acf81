#pragma once
// Resolves a BSP shader name to an RGB image the way the game finds one: the name
// itself as .jpg or .tga, else the first image stage ("map"/"clampMap"/"animMap")
// of the shader script of that name (scripts/*.shader), else a neutral grey
// placeholder. Images are decoded from pk3 bytes with stb_image (OpenCV has no TGA).
#include <opencv2/core.hpp>
#include <string>
#include <unordered_map>

#include "valerant/world/quake3/pk3_archive.h"

namespace valerant::quake3 {

enum class TextureSource { kImage, kShaderStage, kPlaceholder };

struct ResolvedTexture {
  cv::Mat rgb;  // CV_8UC3, RGB, row 0 = t 0 (as the game uploads it)
  TextureSource source = TextureSource::kPlaceholder;
  std::string image_path;  // what was loaded, "" for the placeholder
};

class TextureLibrary {
 public:
  explicit TextureLibrary(const Pk3FileSystem& fs);
  ResolvedTexture resolve(const std::string& shader_name) const;

 private:
  const Pk3FileSystem& fs_;
  std::unordered_map<std::string, std::string> shader_first_image_;  // lower-case name -> image
  cv::Mat decode(const std::string& path) const;  // empty when missing or undecodable
};

}  // namespace valerant::quake3
