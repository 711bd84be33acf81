#include "valerant/world/quake3/texture_library.h"

#include <stb_image.h>

#include <algorithm>
#include <cctype>
#include <opencv2/imgproc.hpp>
#include <vector>

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

// Splits a shader script into lower-case tokens: braces are tokens of their own,
// // and /* */ comments are skipped, quoted strings are one token.
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
      tokens.push_back(lower(text.substr(i + 1, (end == std::string::npos ? text.size() : end) - i - 1)));
      i = end == std::string::npos ? text.size() : end + 1;
    } else {
      const size_t start = i;
      while (i < text.size() && !std::isspace(static_cast<unsigned char>(text[i])) && text[i] != '{' &&
             text[i] != '}')
        ++i;
      tokens.push_back(lower(text.substr(start, i - start)));
    }
  }
  return tokens;
}

// The blend of a stage's "blendFunc <src> <dst>" (or its add/filter/blend shorthand),
// classified like the game's sort: GL_ONE GL_ZERO is no blending at all.
StageRendering::Blend classifyBlend(const std::string& src, const std::string& dst) {
  using Blend = StageRendering::Blend;
  if (src == "gl_one" && dst == "gl_zero") return Blend::kNone;
  if (dst == "gl_one") return Blend::kAdd;
  if ((src == "gl_dst_color" || src == "gl_zero") && (dst == "gl_zero" || dst == "gl_src_color")) return Blend::kFilter;
  return Blend::kAlpha;
}

// The facts of one shader block starting after its opening brace at tokens[i];
// leaves `i` after the closing brace.
TextureLibrary::ShaderScript parseShader(const std::vector<std::string>& tokens, size_t& i) {
  TextureLibrary::ShaderScript script;
  int depth = 1, stage = -1;
  bool blended = false, depth_write = false;
  auto arg = [&](size_t k) -> const std::string& {
    static const std::string none;
    return i + k < tokens.size() ? tokens[i + k] : none;
  };
  for (; i < tokens.size() && depth > 0; ++i) {
    const std::string& t = tokens[i];
    if (t == "{") {
      if (++depth == 2) ++stage;
      continue;
    }
    if (t == "}") {
      --depth;
      continue;
    }
    if (depth != 2) continue;
    if (script.first_image.empty() && (t == "map" || t == "clampmap")) {
      // $lightmap, $whiteimage and *white are engine images, not files.
      if (!arg(1).empty() && arg(1)[0] != '$' && arg(1)[0] != '*') script.first_image = arg(1);
    } else if (script.first_image.empty() && t == "animmap") {
      script.first_image = arg(2);  // animMap <frequency> <first frame> ...
    } else if (stage == 0 && t == "blendfunc") {
      const std::string& a = arg(1);
      if (a == "add") {
        script.stage.blend = classifyBlend("gl_one", "gl_one");
      } else if (a == "filter") {
        script.stage.blend = classifyBlend("gl_dst_color", "gl_zero");
      } else if (a == "blend") {
        script.stage.blend = classifyBlend("gl_src_alpha", "gl_one_minus_src_alpha");
      } else {
        script.stage.blend = classifyBlend(a, arg(2));
      }
      blended = script.stage.blend != StageRendering::Blend::kNone;
    } else if (stage == 0 && t == "alphafunc") {
      using AlphaTest = StageRendering::AlphaTest;
      const std::string& a = arg(1);
      script.stage.alpha_test = a == "gt0"     ? AlphaTest::kGreaterThan0
                                : a == "lt128" ? AlphaTest::kLessThan128
                                : a == "ge128" ? AlphaTest::kAtLeast128
                                               : AlphaTest::kNone;
    } else if (stage == 0 && t == "depthwrite") {
      depth_write = true;
    }
  }
  // As in the game, a blended first stage writes depth only when it says so.
  script.stage.depth_write = !blended || depth_write;
  return script;
}

// Records every shader of `text` not already known (the first definition wins).
void parseShaderScript(const std::string& text, std::unordered_map<std::string, TextureLibrary::ShaderScript>& out) {
  const std::vector<std::string> tokens = tokenize(text);
  size_t i = 0;
  while (i < tokens.size()) {
    const std::string& name = tokens[i++];
    if (i >= tokens.size() || tokens[i] != "{") continue;  // stray token: resynchronise
    ++i;
    TextureLibrary::ShaderScript script = parseShader(tokens, i);
    out.emplace(name, std::move(script));
  }
}

}  // namespace

TextureLibrary::TextureLibrary(const Pk3FileSystem& fs) : fs_(fs) {
  for (const auto& path : fs.list("scripts/", ".shader")) {
    const auto bytes = fs.read(path);
    if (bytes) parseShaderScript(std::string(bytes->begin(), bytes->end()), scripts_);
  }
}

bool TextureLibrary::decode(const std::string& path, cv::Mat& rgb, cv::Mat& alpha) const {
  const auto bytes = fs_.read(path);
  if (!bytes || bytes->empty()) return false;
  int w = 0, h = 0, channels = 0;
  stbi_uc* pixels = stbi_load_from_memory(bytes->data(), static_cast<int>(bytes->size()), &w, &h, &channels, 4);
  if (!pixels) return false;
  const cv::Mat rgba(h, w, CV_8UC4, pixels);
  cv::cvtColor(rgba, rgb, cv::COLOR_RGBA2RGB);
  alpha.release();
  if (channels == 2 || channels == 4) {
    cv::extractChannel(rgba, alpha, 3);
    double min_alpha = 0;
    cv::minMaxLoc(alpha, &min_alpha);
    if (min_alpha >= 255) alpha.release();  // an alpha channel that is opaque everywhere
  }
  stbi_image_free(pixels);
  return true;
}

ResolvedTexture TextureLibrary::resolve(const std::string& shader_name) const {
  ResolvedTexture out;
  const std::string name = lower(shader_name), base = stripExtension(name);
  const auto script = scripts_.count(name) ? scripts_.find(name) : scripts_.find(base);
  if (script != scripts_.end()) out.stage = script->second.stage;

  auto load = [&](const std::string& image, TextureSource source) {
    for (const char* ext : {".jpg", ".tga"}) {
      if (decode(image + ext, out.rgb, out.alpha)) {
        out.source = source;
        out.image_path = image + ext;
        return true;
      }
    }
    return false;
  };
  if (load(base, TextureSource::kImage)) return out;
  if (script != scripts_.end() && !script->second.first_image.empty() &&
      load(stripExtension(script->second.first_image), TextureSource::kShaderStage))
    return out;
  // A neutral grey keeps the lightmap's shading visible without inventing texture.
  out.rgb = cv::Mat(8, 8, CV_8UC3, cv::Scalar(128, 128, 128));
  out.alpha.release();
  out.source = TextureSource::kPlaceholder;
  return out;
}

}  // namespace valerant::quake3
