#include "valerant/dataset/texture_shuffle.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <set>

#include "valerant/common/error.h"
#include "valerant/world/quake3/bsp.h"
#include "valerant/world/quake3/texture_library.h"

namespace valerant::dataset {

TexturePool buildTexturePool(const quake3::Pk3FileSystem& fs, const std::vector<std::string>& maps, int max_side) {
  if (max_side < 1) throw InputError("texture pool", "max_side must be positive");
  std::set<std::string> shaders;
  for (const auto& map : maps) {
    const auto bytes = fs.read("maps/" + map + ".bsp");
    if (!bytes) throw InputError("map '" + map + "'", "not found in the mounted pk3s (texture pool)");
    const quake3::BspMap bsp = quake3::parseBsp(*bytes, map);
    for (const auto& s : bsp.shaders)
      if (!(s.surface_flags & (quake3::kSurfSky | quake3::kSurfNoDraw))) shaders.insert(s.name);
  }
  const quake3::TextureLibrary library(fs);
  std::map<std::string, cv::Mat> by_path;
  for (const auto& name : shaders) {
    quake3::ResolvedTexture t = library.resolve(name);
    if (t.source == quake3::TextureSource::kPlaceholder || !t.alpha.empty() ||
        t.stage.blend != quake3::StageRendering::Blend::kNone ||
        t.stage.alpha_test != quake3::StageRendering::AlphaTest::kNone || by_path.count(t.image_path))
      continue;
    const int longest = std::max(t.rgb.cols, t.rgb.rows);
    if (longest > max_side) {
      const double f = static_cast<double>(max_side) / longest;
      cv::resize(t.rgb, t.rgb, cv::Size(std::max(1, static_cast<int>(t.rgb.cols * f)),
                                        std::max(1, static_cast<int>(t.rgb.rows * f))),
                 0, 0, cv::INTER_AREA);
    }
    by_path.emplace(t.image_path, t.rgb);
  }
  TexturePool pool;
  for (auto& [path, image] : by_path) {
    pool.paths.push_back(path);
    pool.images.push_back(image);
  }
  return pool;
}

std::map<int, cv::Mat> shuffleTextures(const std::vector<int>& shaders, const TextureShuffle& shuffle,
                                       std::mt19937_64& rng) {
  std::map<int, cv::Mat> out;
  if (!shuffle.enabled()) return out;
  std::uniform_real_distribution<double> unit(0.0, 1.0), gain(0.6, 1.4);
  std::uniform_int_distribution<int> channel(30, 230);
  std::uniform_int_distribution<size_t> pick(0, shuffle.pool->images.size() - 1);
  for (int shader : shaders) {
    if (unit(rng) >= shuffle.probability) continue;
    if (unit(rng) < shuffle.flat_fraction) {
      const int r = channel(rng), g = channel(rng), b = channel(rng);
      out[shader] = cv::Mat(4, 4, CV_8UC3, cv::Scalar(r, g, b));
      continue;
    }
    const cv::Mat& image = shuffle.pool->images[pick(rng)];
    if (unit(rng) < shuffle.tint_probability) {
      const double r = gain(rng), g = gain(rng), b = gain(rng);
      cv::Mat tinted;
      cv::multiply(image, cv::Scalar(r, g, b), tinted);  // saturating
      out[shader] = tinted;
    } else {
      out[shader] = image;
    }
  }
  return out;
}

}  // namespace valerant::dataset
