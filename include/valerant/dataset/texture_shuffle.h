#pragma once
// Domain randomisation for the depth prior's data (valerant_dataset --texture-shuffle):
// per sequence, each surface that is drawn opaque may wear another texture, drawn from
// the images of every training map, or a flat colour, so the geometry (and the depth
// label) stays while the appearance varies. Lightmaps and vertex colours still light the
// surface; sky stays the renderer's clear colour; translucent and alpha-tested shaders
// keep their own image (another one would change which pixels they cover).
#include <map>
#include <random>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "valerant/world/quake3/pk3_archive.h"

namespace valerant::dataset {

struct TexturePool {
  std::vector<std::string> paths;  // image paths in the pk3s, sorted
  std::vector<cv::Mat> images;     // CV_8UC3 RGB, longest side at most the pool's max_side
};

// The images of every drawn, non-sky shader of `maps` whose first stage is opaque without
// alpha test and that resolves to an image (not the grey placeholder), each image once,
// sorted by path. Throws InputError naming a map that `fs` does not hold.
TexturePool buildTexturePool(const quake3::Pk3FileSystem& fs, const std::vector<std::string>& maps,
                             int max_side = 128);

struct TextureShuffle {
  const TexturePool* pool = nullptr;  // none or empty: nothing is shuffled
  double probability = 0;             // per retexturable shader and sequence
  double flat_fraction = 0.2;         // of the shuffled ones: a flat random colour
  double tint_probability = 0.5;      // of the pool images: per-channel gains in [0.6, 1.4]
  bool enabled() const { return pool && !pool->images.empty() && probability > 0; }
};

// One sequence's assignment for OsMesaRenderer::overrideTextures: each of `shaders` with
// `probability` gets a pool image (tinted or not) or a flat colour; deterministic in `rng`.
std::map<int, cv::Mat> shuffleTextures(const std::vector<int>& shaders, const TextureShuffle& shuffle,
                                       std::mt19937_64& rng);

}  // namespace valerant::dataset
