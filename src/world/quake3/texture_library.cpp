#include "valerant/world/quake3/texture_library.h"

#include <stb_image.h>

#include <algorithm>
#include <cctype>
#include <sstream>

namespace valerant::quake3 {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string stripExtension(const std::string& path) {
  const size_t dot = path.rfind('.');
  const size_t slash = path.rfind('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path;
  return path.substr(0, dot);
}

// Splits a shader script into tokens: braces are tokens of their own, // and /* */
// comments are skipped, quoted strings are one token.
std::vector<std::string> tokenize(const std::string& text) {
  std::vector<std::string> tokens;
  size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '/') {
      while (i < text.size() && text[i] != '\n') ++i;
    } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
      const size_t end = text.find("*/", i + 2);
      i = end == std::string::npos ? text.size() : end + 2;
    } else if (c == '{' || c == '}') {
      tokens.emplace_back(1, c);
      ++i;
    } else if (c == '"') {
      const size_t end = text.find('"', i + 1);
      tokens.push_back(text.substr(i + 1, (end == std::string::npos ? text.size() : end) - i - 1));
      i = end == std::string::npos ? text.size() : end + 1;
    } else {
      const size_t start = i;
      while (i < text.size() && !std::isspace(static_cast<unsigned char>(text[i])) && text[i] != '{' && text[i] != '}')
        ++i;
      tokens.push_back(text.substr(start, i - start));
    }
  }
  return tokens;
}

// Records, for every shader in `text`, the first image its stages draw.
void parseShaderScript(const std::string& text, std::unordered_map<std::string, std::string>& first_image) {
  const std::vector<std::string> tokens = tokenize(text);
  size_t i = 0;
  while (i < tokens.size()) {
    const std::string name = lower(tokens[i++]);
    if (i >= tokens.size() || tokens[i] != "{") continue;  // stray token: resynchronise
    ++i;
    int depth = 1;
    std::string image;
    while (i < tokens.size() && depth > 0) {
      const std::string t = lower(tokens[i]);
      if (t == "{") {
        ++depth;
      } else if (t == "}") {
        --depth;
      } else if (depth == 2 && image.empty() && (t == "map" || t == "clampmap") && i + 1 < tokens.size()) {
        const std::string arg = lower(tokens[i + 1]);
        if (arg[0] != '$') image = arg;  // $lightmap, $whiteimage are not images
      } else if (depth == 2 && image.empty() && t == "animmap" && i + 2 < tokens.size()) {
        image = lower(tokens[i + 2]);  // animMap <frequency> <first frame> ...
      }
      ++i;
    }
    if (!image.empty() && !first_image.count(name)) first_image[name] = image;
  }
}

}  // namespace

TextureLibrary::TextureLibrary(const Pk3FileSystem& fs) : fs_(fs) {
  for (const auto& path : fs.list("scripts/", ".shader")) {
    const auto bytes = fs.read(path);
    if (bytes) parseShaderScript(std::string(bytes->begin(), bytes->end()), shader_first_image_);
  }
}

cv::Mat TextureLibrary::decode(const std::string& path) const {
  const auto bytes = fs_.read(path);
  if (!bytes || bytes->empty()) return {};
  int w = 0, h = 0, channels = 0;
  stbi_uc* pixels = stbi_load_from_memory(bytes->data(), static_cast<int>(bytes->size()), &w, &h, &channels, 3);
  if (!pixels) return {};
  cv::Mat rgb = cv::Mat(h, w, CV_8UC3, pixels).clone();
  stbi_image_free(pixels);
  return rgb;
}

ResolvedTexture TextureLibrary::resolve(const std::string& shader_name) const {
  ResolvedTexture out;
  const std::string base = stripExtension(lower(shader_name));
  for (const char* ext : {".jpg", ".tga"}) {
    out.rgb = decode(base + ext);
    if (!out.rgb.empty()) {
      out.source = TextureSource::kImage;
      out.image_path = base + ext;
      return out;
    }
  }
  if (auto it = shader_first_image_.find(lower(shader_name)); it != shader_first_image_.end()) {
    const std::string image = stripExtension(it->second);
    for (const char* ext : {".jpg", ".tga"}) {
      out.rgb = decode(image + ext);
      if (!out.rgb.empty()) {
        out.source = TextureSource::kShaderStage;
        out.image_path = image + ext;
        return out;
      }
    }
  }
  // A neutral grey keeps the lightmap's shading visible without inventing texture.
  out.rgb = cv::Mat(8, 8, CV_8UC3, cv::Scalar(128, 128, 128));
  out.source = TextureSource::kPlaceholder;
  return out;
}

}  // namespace valerant::quake3
