#include "valerant/world/quake3/osmesa_renderer.h"

#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <opencv2/imgproc.hpp>

#include "valerant/common/error.h"

namespace valerant::quake3 {
namespace {

// The game brightens lightmaps by its overbright shift (R_ColorShiftLightingBytes with
// r_mapOverBrightBits 2 and no hardware gamma): x4, scaled back so no channel clips,
// which keeps the hue of bright light instead of washing it to white.
constexpr int kLightmapShift = 2;

std::vector<uint8_t> brightenLightmap(const std::vector<uint8_t>& rgb) {
  std::vector<uint8_t> out(rgb.size());
  for (size_t i = 0; i + 2 < rgb.size(); i += 3) {
    int c[3] = {rgb[i] << kLightmapShift, rgb[i + 1] << kLightmapShift, rgb[i + 2] << kLightmapShift};
    const int max = std::max({c[0], c[1], c[2]});
    for (int k = 0; k < 3; ++k) out[i + k] = static_cast<uint8_t>(max > 255 ? c[k] * 255 / max : c[k]);
  }
  return out;
}

GLuint uploadTexture(const cv::Mat& rgb, bool repeat) {
  GLuint id = 0;
  glGenTextures(1, &id);
  glBindTexture(GL_TEXTURE_2D, id);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  const cv::Mat pixels = rgb.isContinuous() ? rgb : rgb.clone();
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, pixels.cols, pixels.rows, 0, GL_RGB, GL_UNSIGNED_BYTE, pixels.data);
  glGenerateMipmap(GL_TEXTURE_2D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  const GLint wrap = repeat ? GL_REPEAT : GL_CLAMP_TO_EDGE;
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap);
  return id;
}

// Interleaved vertex layout uploaded once into a vertex buffer.
struct GpuVertex {
  float position[3];
  float texcoord[2];
  float lmcoord[2];
  uint8_t color[4];
};

// Plane form (a, b, c, d) of the six frustum planes, inside where a x + b y + c z + d >= 0
// (Gribb and Hartmann: rows of the combined projection-view matrix).
using Frustum = std::array<Eigen::Vector4f, 6>;

Frustum frustumPlanes(const Eigen::Matrix4f& clip) {
  Frustum f;
  for (int i = 0; i < 3; ++i) {
    f[2 * i] = clip.row(3) + clip.row(i);
    f[2 * i + 1] = clip.row(3) - clip.row(i);
  }
  return f;
}

bool boxInFrustum(const Frustum& frustum, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  for (const auto& p : frustum) {
    // The box corner farthest along the plane normal.
    const Eigen::Vector3f corner(p.x() >= 0 ? hi.x() : lo.x(), p.y() >= 0 ? hi.y() : lo.y(),
                                 p.z() >= 0 ? hi.z() : lo.z());
    if (p.head<3>().dot(corner) + p.w() < 0) return false;
  }
  return true;
}

}  // namespace

struct OsMesaRenderer::Impl {
  const BspMap& map;
  const MapGeometry& geometry;
  RenderOptions options;
  OSMesaContext context = nullptr;
  std::vector<uint8_t> colour_buffer;
  GLuint vertex_buffer = 0;
  std::vector<GLuint> shader_textures;    // per BSP shader (0 when unused)
  std::vector<GLuint> lightmap_textures;  // per lightmap
  // One batch per (shader, lightmap) pair: surfaces drawn with the same textures.
  struct Batch {
    int shader, lightmap;
    bool sky;
    std::vector<uint32_t> indices;  // rebuilt every frame
  };
  std::vector<Batch> batches;
  std::vector<int> face_batch;      // face -> batch, -1 when not drawn
  std::vector<int> model_faces;     // faces of brush models (doors, platforms): not in leaves
  std::vector<uint32_t> face_stamp;  // frame number a face was last queued in
  uint32_t frame = 0;
  std::vector<float> depth_buffer;
  std::vector<uint8_t> stencil_buffer;

  Impl(const BspMap& m, const MapGeometry& g, const RenderOptions& o) : map(m), geometry(g), options(o) {}
  ~Impl() {
    if (context) OSMesaDestroyContext(context);
  }

  void queueFace(int face) {
    if (face < 0 || static_cast<size_t>(face) >= face_batch.size()) return;
    const int b = face_batch[face];
    if (b < 0 || face_stamp[face] == frame) return;
    face_stamp[face] = frame;
    const DrawSurface& s = geometry.surfaces[face];
    auto& out = batches[b].indices;
    out.insert(out.end(), geometry.indices.begin() + s.first_index,
               geometry.indices.begin() + s.first_index + s.num_indices);
  }
};

OsMesaRenderer::OsMesaRenderer(const BspMap& map, const MapGeometry& geometry, const TextureLibrary& textures,
                               const CameraIntrinsics& intrinsics, const RenderOptions& options)
    : impl_(std::make_unique<Impl>(map, geometry, options)), intrinsics_(intrinsics) {
  Impl& r = *impl_;
  r.context = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, nullptr);
  if (!r.context) throw InputError("OSMesa", "cannot create an offscreen GL context");
  r.colour_buffer.resize(static_cast<size_t>(intrinsics.width) * intrinsics.height * 4);
  if (!OSMesaMakeCurrent(r.context, r.colour_buffer.data(), GL_UNSIGNED_BYTE, intrinsics.width, intrinsics.height))
    throw InputError("OSMesa", "cannot make the offscreen context current");
  OSMesaPixelStore(OSMESA_Y_UP, 1);

  // Textures for every shader a drawn surface uses, and every lightmap.
  r.shader_textures.assign(map.shaders.size(), 0);
  std::map<std::pair<int, int>, int> batch_of;
  r.face_batch.assign(map.faces.size(), -1);
  for (size_t f = 0; f < geometry.surfaces.size(); ++f) {
    const DrawSurface& s = geometry.surfaces[f];
    if (s.num_indices == 0) continue;
    if (!s.sky && r.shader_textures[s.shader] == 0) {
      const ResolvedTexture t = textures.resolve(map.shaders[s.shader].name);
      r.shader_textures[s.shader] = uploadTexture(t.rgb, true);
      stats_.images += t.source == TextureSource::kImage;
      stats_.shader_stages += t.source == TextureSource::kShaderStage;
      stats_.placeholders += t.source == TextureSource::kPlaceholder;
    }
    const auto key = std::make_pair(s.shader, s.lightmap);
    auto it = batch_of.find(key);
    if (it == batch_of.end()) {
      it = batch_of.emplace(key, static_cast<int>(r.batches.size())).first;
      r.batches.push_back({s.shader, s.lightmap, s.sky, {}});
    }
    r.face_batch[f] = it->second;
  }
  for (const auto& lm : map.lightmaps) {
    std::vector<uint8_t> bright = brightenLightmap(lm.rgb);
    const cv::Mat rgb(BspLightmap::kSize, BspLightmap::kSize, CV_8UC3, bright.data());
    r.lightmap_textures.push_back(uploadTexture(rgb, false));
  }
  for (size_t m = 1; m < map.models.size(); ++m)
    for (int f = map.models[m].first_face; f < map.models[m].first_face + map.models[m].num_faces; ++f)
      r.model_faces.push_back(f);
  r.face_stamp.assign(map.faces.size(), 0);

  std::vector<GpuVertex> vertices(geometry.vertices.size());
  for (size_t i = 0; i < vertices.size(); ++i) {
    const BspVertex& v = geometry.vertices[i];
    std::copy(v.position.data(), v.position.data() + 3, vertices[i].position);
    std::copy(v.texcoord.data(), v.texcoord.data() + 2, vertices[i].texcoord);
    std::copy(v.lmcoord.data(), v.lmcoord.data() + 2, vertices[i].lmcoord);
    std::copy(v.color.begin(), v.color.end(), vertices[i].color);
  }
  glGenBuffers(1, &r.vertex_buffer);
  glBindBuffer(GL_ARRAY_BUFFER, r.vertex_buffer);
  glBufferData(GL_ARRAY_BUFFER, vertices.size() * sizeof(GpuVertex), vertices.data(), GL_STATIC_DRAW);

  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  glDisable(GL_CULL_FACE);  // BSP windings differ between faces and patches; draw both sides
  glViewport(0, 0, intrinsics.width, intrinsics.height);
  r.depth_buffer.resize(static_cast<size_t>(intrinsics.width) * intrinsics.height);
  r.stencil_buffer.resize(r.depth_buffer.size());
  if (glGetError() != GL_NO_ERROR) throw InputError("OSMesa", "GL setup failed");
}

OsMesaRenderer::~OsMesaRenderer() = default;

RenderedView OsMesaRenderer::render(const Eigen::Isometry3f& camera_to_world) {
  Impl& r = *impl_;
  const int w = intrinsics_.width, h = intrinsics_.height;
  OSMesaMakeCurrent(r.context, r.colour_buffer.data(), GL_UNSIGNED_BYTE, w, h);

  // Projection matching the pinhole model with OpenCV's pixel-centre convention
  // (a pixel's centre at integer coordinates, hence the half-pixel shift).
  const float n = r.options.near_plane, f = r.options.far_plane;
  const float cx = static_cast<float>(intrinsics_.cx) + 0.5f, cy = static_cast<float>(intrinsics_.cy) + 0.5f;
  Eigen::Matrix4f projection = Eigen::Matrix4f::Zero();
  projection(0, 0) = 2.f * static_cast<float>(intrinsics_.fx) / w;
  projection(0, 2) = 1.f - 2.f * cx / w;
  projection(1, 1) = 2.f * static_cast<float>(intrinsics_.fy) / h;
  projection(1, 2) = 2.f * cy / h - 1.f;
  projection(2, 2) = -(f + n) / (f - n);
  projection(2, 3) = -2.f * f * n / (f - n);
  projection(3, 2) = -1.f;
  // Optical frame (x right, y down, z forward) to GL camera (x right, y up, z back).
  const Eigen::Matrix4f optical_to_gl = Eigen::Vector4f(1, -1, -1, 1).asDiagonal();
  const Eigen::Matrix4f view = optical_to_gl * camera_to_world.inverse().matrix();
  const Frustum frustum = frustumPlanes(projection * view);

  // Potentially visible faces: the PVS row of the camera's cluster, cut by the frustum.
  ++r.frame;
  for (auto& b : r.batches) b.indices.clear();
  const Eigen::Vector3f eye = camera_to_world.translation();
  const int camera_cluster = r.map.leafs[r.map.leafAt(eye)].cluster;
  const bool use_pvs = r.options.use_pvs && camera_cluster >= 0;  // inside a wall: no PVS row
  for (const BspLeaf& leaf : r.map.leafs) {
    if (leaf.cluster < 0) continue;
    if (use_pvs && !r.map.visibility.visible(camera_cluster, leaf.cluster)) continue;
    if (!boxInFrustum(frustum, leaf.mins.cast<float>(), leaf.maxs.cast<float>())) continue;
    for (int k = 0; k < leaf.num_leaf_faces; ++k) r.queueFace(r.map.leaf_faces[leaf.first_leaf_face + k]);
  }
  for (int face : r.model_faces) {
    const DrawSurface& s = r.geometry.surfaces[face];
    if (s.num_indices && boxInFrustum(frustum, s.bounds.min(), s.bounds.max())) r.queueFace(face);
  }

  const cv::Vec3b& sky = r.options.sky_rgb;
  glClearColor(sky[0] / 255.f, sky[1] / 255.f, sky[2] / 255.f, 1.f);
  glClearStencil(0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
  glMatrixMode(GL_PROJECTION);
  glLoadMatrixf(projection.data());
  glMatrixMode(GL_MODELVIEW);
  glLoadMatrixf(view.data());

  glBindBuffer(GL_ARRAY_BUFFER, r.vertex_buffer);
  glEnableClientState(GL_VERTEX_ARRAY);
  glVertexPointer(3, GL_FLOAT, sizeof(GpuVertex), reinterpret_cast<void*>(offsetof(GpuVertex, position)));
  glClientActiveTexture(GL_TEXTURE0);
  glEnableClientState(GL_TEXTURE_COORD_ARRAY);
  glTexCoordPointer(2, GL_FLOAT, sizeof(GpuVertex), reinterpret_cast<void*>(offsetof(GpuVertex, texcoord)));
  glClientActiveTexture(GL_TEXTURE1);
  glEnableClientState(GL_TEXTURE_COORD_ARRAY);
  glTexCoordPointer(2, GL_FLOAT, sizeof(GpuVertex), reinterpret_cast<void*>(offsetof(GpuVertex, lmcoord)));
  glColorPointer(4, GL_UNSIGNED_BYTE, sizeof(GpuVertex), reinterpret_cast<void*>(offsetof(GpuVertex, color)));

  // Sky faces mark the stencil so their pixels report no depth, like an open sky.
  glEnable(GL_STENCIL_TEST);
  glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
  for (const auto& b : r.batches) {
    if (b.indices.empty()) continue;
    glStencilFunc(GL_ALWAYS, b.sky ? 1 : 0, 0xff);
    if (b.sky) {
      glActiveTexture(GL_TEXTURE1);
      glDisable(GL_TEXTURE_2D);
      glActiveTexture(GL_TEXTURE0);
      glDisable(GL_TEXTURE_2D);
      glDisableClientState(GL_COLOR_ARRAY);
      glColor3ub(sky[0], sky[1], sky[2]);
    } else {
      glActiveTexture(GL_TEXTURE0);
      glEnable(GL_TEXTURE_2D);
      glBindTexture(GL_TEXTURE_2D, r.shader_textures[b.shader]);
      glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
      glActiveTexture(GL_TEXTURE1);
      if (b.lightmap >= 0) {
        glEnable(GL_TEXTURE_2D);
        glBindTexture(GL_TEXTURE_2D, r.lightmap_textures[b.lightmap]);
        glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
        glDisableClientState(GL_COLOR_ARRAY);
        glColor3ub(255, 255, 255);
      } else {
        glDisable(GL_TEXTURE_2D);  // vertex colours carry the light instead
        glEnableClientState(GL_COLOR_ARRAY);
      }
    }
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(b.indices.size()), GL_UNSIGNED_INT, b.indices.data());
  }
  glDisable(GL_STENCIL_TEST);
  glFinish();

  // OSMESA_Y_UP: row 0 of the buffer is the bottom row; flip to the image convention.
  RenderedView view_out;
  const cv::Mat rgba(h, w, CV_8UC4, r.colour_buffer.data());
  cv::cvtColor(rgba, view_out.rgb, cv::COLOR_RGBA2RGB);
  cv::flip(view_out.rgb, view_out.rgb, 0);
  glReadPixels(0, 0, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, r.depth_buffer.data());
  glReadPixels(0, 0, w, h, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, r.stencil_buffer.data());
  view_out.depth.create(h, w, CV_32F);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int row = 0; row < h; ++row) {
    const float* d = r.depth_buffer.data() + static_cast<size_t>(h - 1 - row) * w;
    const uint8_t* s = r.stencil_buffer.data() + static_cast<size_t>(h - 1 - row) * w;
    float* out = view_out.depth.ptr<float>(row);
    for (int col = 0; col < w; ++col) {
      // Window depth d in [0, 1] back to the distance along the optical axis.
      out[col] = (s[col] || d[col] >= 1.f) ? nan : n * f / (f - d[col] * (f - n));
    }
  }
  return view_out;
}

}  // namespace valerant::quake3
