#include "valerant/map/mesh_renderer.h"

#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GL/osmesa.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <opencv2/imgproc.hpp>

#include "valerant/common/error.h"

namespace valerant {
namespace {

// Look of the quick-look pictures (not method parameters): a light from above and a
// little aside, enough ambient light that surfaces facing away keep their colour.
const Eigen::Vector3f kLightDirection = Eigen::Vector3f(0.3f, 1.0f, 0.5f).normalized();
constexpr float kAmbient = 0.45f;
const cv::Scalar kBackground(30, 30, 38);
const cv::Scalar kWalkableRgb(60, 220, 90);
constexpr double kWalkableShade = 0.3;  // opacity of the walkable fill
const cv::Scalar kPathRgb(255, 210, 0);
const cv::Scalar kSpawnRgb(40, 110, 255);
constexpr float kOrbitMargin = 1.05f;  // the mesh fills the view with a small border
// Game lighting is dark: colours are scaled so the median vertex reaches this level,
// by at most kMaxGain.
constexpr float kTargetMedianLevel = 120.f;
constexpr float kMaxGain = 3.f;

Eigen::Matrix4f lookAt(const Eigen::Vector3f& eye, const Eigen::Vector3f& target, const Eigen::Vector3f& up) {
  const Eigen::Vector3f back = (eye - target).normalized();
  const Eigen::Vector3f right = up.cross(back).normalized();
  const Eigen::Vector3f true_up = back.cross(right);
  Eigen::Matrix4f view = Eigen::Matrix4f::Identity();
  view.block<1, 3>(0, 0) = right.transpose();
  view.block<1, 3>(1, 0) = true_up.transpose();
  view.block<1, 3>(2, 0) = back.transpose();
  view.block<3, 1>(0, 3) = -view.block<3, 3>(0, 0) * eye;
  return view;
}

Eigen::Matrix4f perspective(float fov_x_rad, float aspect, float near, float far) {
  const float fx = 1.f / std::tan(fov_x_rad / 2);
  Eigen::Matrix4f p = Eigen::Matrix4f::Zero();
  p(0, 0) = fx;
  p(1, 1) = fx * aspect;
  p(2, 2) = -(far + near) / (far - near);
  p(2, 3) = -2.f * far * near / (far - near);
  p(3, 2) = -1.f;
  return p;
}

Eigen::Matrix4f orthographic(float half_width, float half_height, float near, float far) {
  Eigen::Matrix4f p = Eigen::Matrix4f::Identity();
  p(0, 0) = 1.f / half_width;
  p(1, 1) = 1.f / half_height;
  p(2, 2) = -2.f / (far - near);
  p(2, 3) = -(far + near) / (far - near);
  return p;
}

Eigen::AlignedBox3f bounds(const SurfaceMesh& mesh) {
  Eigen::AlignedBox3f box;
  for (const auto& p : mesh.positions) box.extend(p);
  return box;
}

}  // namespace

struct MeshRenderer::Impl {
  int width, height;
  OSMesaContext context = nullptr;
  std::vector<uint8_t> colour_buffer;
  ~Impl() {
    if (context) OSMesaDestroyContext(context);
  }
};

MeshRenderer::MeshRenderer(int width, int height) : impl_(std::make_unique<Impl>()) {
  impl_->width = width;
  impl_->height = height;
  impl_->context = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
  if (!impl_->context) throw InputError("OSMesa", "cannot create an offscreen GL context");
  impl_->colour_buffer.resize(static_cast<size_t>(width) * height * 4);
}

MeshRenderer::~MeshRenderer() = default;

cv::Mat MeshRenderer::render(const SurfaceMesh& mesh, const Eigen::Matrix4f& view, const Eigen::Matrix4f& projection) {
  Impl& r = *impl_;
  if (!OSMesaMakeCurrent(r.context, r.colour_buffer.data(), GL_UNSIGNED_BYTE, r.width, r.height))
    throw InputError("OSMesa", "cannot make the offscreen context current");
  OSMesaPixelStore(OSMESA_Y_UP, 1);
  // Mesa writes past its buffers for a canvas beyond its limit instead of failing.
  GLint max_dims[2] = {0, 0};
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, max_dims);
  if (r.width > max_dims[0] || r.height > max_dims[1])
    throw InputError("OSMesa", "a " + std::to_string(r.width) + " x " + std::to_string(r.height) +
                                   " picture exceeds the rasteriser's limit of " + std::to_string(max_dims[0]) +
                                   " x " + std::to_string(max_dims[1]) + " pixels");
  glViewport(0, 0, r.width, r.height);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  glDisable(GL_CULL_FACE);  // the scan is open: both sides of a surface can face the camera
  glClearColor(kBackground[0] / 255.f, kBackground[1] / 255.f, kBackground[2] / 255.f, 1.f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glMatrixMode(GL_PROJECTION);
  glLoadMatrixf(projection.data());
  glMatrixMode(GL_MODELVIEW);
  glLoadMatrixf(view.data());

  // Shaded vertex colours, computed here rather than by GL lighting, whose two-sided
  // mode would darken any triangle whose winding disagrees with its normals.
  std::vector<float> levels(mesh.colours.size());
  for (size_t i = 0; i < mesh.colours.size(); ++i)
    levels[i] = (mesh.colours[i][0] + mesh.colours[i][1] + mesh.colours[i][2]) / 3.f;
  float gain = 1;
  if (!levels.empty()) {
    std::nth_element(levels.begin(), levels.begin() + levels.size() / 2, levels.end());
    gain = std::clamp(kTargetMedianLevel / std::max(levels[levels.size() / 2], 1.f), 1.f, kMaxGain);
  }
  std::vector<uint8_t> shaded(mesh.colours.size() * 3);
  for (size_t i = 0; i < mesh.colours.size(); ++i) {
    const float light = gain * (kAmbient + (1 - kAmbient) * std::abs(mesh.normals[i].dot(kLightDirection)));
    for (int k = 0; k < 3; ++k) shaded[3 * i + k] = static_cast<uint8_t>(std::min(255.f, mesh.colours[i][k] * light));
  }
  if (!mesh.triangles.empty()) {
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_COLOR_ARRAY);
    glVertexPointer(3, GL_FLOAT, sizeof(Eigen::Vector3f), mesh.positions.data());
    glColorPointer(3, GL_UNSIGNED_BYTE, 0, shaded.data());
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(mesh.triangles.size() * 3), GL_UNSIGNED_INT,
                   mesh.triangles.data());
    glDisableClientState(GL_COLOR_ARRAY);
    glDisableClientState(GL_VERTEX_ARRAY);
  }
  glFinish();
  if (glGetError() != GL_NO_ERROR) throw InputError("OSMesa", "rendering the mesh failed");

  // OSMESA_Y_UP: row 0 of the buffer is the bottom row; flip to the image convention.
  cv::Mat rgb;
  cv::cvtColor(cv::Mat(r.height, r.width, CV_8UC4, r.colour_buffer.data()), rgb, cv::COLOR_RGBA2RGB);
  cv::flip(rgb, rgb, 0);
  return rgb;
}

std::vector<cv::Mat> renderOrbit(const SurfaceMesh& full_mesh, const ExportConfig& config) {
  const SurfaceMesh mesh = cutAbove(full_mesh, static_cast<float>(config.render_cut_eye_heights));
  if (mesh.triangles.empty()) return {};
  const Eigen::Vector3f centre = bounds(mesh).center();
  const float aspect = static_cast<float>(config.render_width) / config.render_height;
  const float fov_x = static_cast<float>(config.orbit_fov_deg * M_PI / 180);
  const float tan_x = std::tan(fov_x / 2), tan_y = tan_x / aspect;
  const float elevation = static_cast<float>(config.orbit_elevation_deg * M_PI / 180);
  MeshRenderer renderer(config.render_width, config.render_height);
  std::vector<cv::Mat> views;
  for (int i = 0; i < config.orbit_views; ++i) {
    const float azimuth = static_cast<float>(2 * M_PI * i / config.orbit_views);
    const Eigen::Vector3f back(std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
                               std::cos(elevation) * std::cos(azimuth));
    // Straight from above the view's up is the spawn's heading (-Z).
    const Eigen::Vector3f up =
        std::abs(back.y()) > 0.999f ? Eigen::Vector3f(-Eigen::Vector3f::UnitZ()) : Eigen::Vector3f::UnitY();
    const Eigen::Vector3f right = up.cross(back).normalized(), true_up = back.cross(right);
    // The nearest camera distance from the centre that keeps every vertex in view.
    float distance = 0, nearest = std::numeric_limits<float>::max(), farthest = 0;
    for (const auto& p : mesh.positions) {
      const Eigen::Vector3f q = p - centre;
      const float z = q.dot(back);
      distance = std::max({distance, z + std::abs(q.dot(right)) / tan_x, z + std::abs(q.dot(true_up)) / tan_y});
    }
    distance *= kOrbitMargin;
    for (const auto& p : mesh.positions) {
      const float depth = distance - (p - centre).dot(back);
      nearest = std::min(nearest, depth);
      farthest = std::max(farthest, depth);
    }
    const Eigen::Vector3f eye = centre + distance * back;
    // Clip planes just outside the mesh's depth range.
    views.push_back(renderer.render(mesh, lookAt(eye, centre, up),
                                    perspective(fov_x, aspect, std::max(0.9f * nearest, 1e-3f * distance),
                                                1.1f * farthest)));
  }
  return views;
}

cv::Mat renderOverview(const SurfaceMesh& full_mesh, const WalkableArea& walkable, const AssetNodes& nodes,
                       const ExportConfig& config) {
  const SurfaceMesh mesh = cutAbove(full_mesh, static_cast<float>(config.render_cut_eye_heights));
  if (mesh.triangles.empty()) return {};
  const Eigen::AlignedBox3f box = bounds(mesh);
  // A runaway SLAM scale can make the map kilometres wide: past overview_max_side_px
  // the scale shrinks so the picture keeps that size.
  const double extent = std::max<double>(box.sizes().x(), box.sizes().z());
  const double ppm = std::min(config.overview_pixels_per_metre, config.overview_max_side_px / std::max(extent, 1e-9));
  const int max_side = config.overview_max_side_px;
  const int width = std::clamp(static_cast<int>(std::ceil(box.sizes().x() * ppm)), 1, max_side);
  const int height = std::clamp(static_cast<int>(std::ceil(box.sizes().z() * ppm)), 1, max_side);
  const float half_w = 0.5f * width / static_cast<float>(ppm), half_h = 0.5f * height / static_cast<float>(ppm);
  const Eigen::Vector3f centre = box.center();
  // Looking straight down with -Z up: +X is right, +Z down the image.
  const Eigen::Vector3f eye(centre.x(), box.max().y() + 1.f, centre.z());
  MeshRenderer renderer(width, height);
  cv::Mat image = renderer.render(mesh, lookAt(eye, eye - Eigen::Vector3f::UnitY(), -Eigen::Vector3f::UnitZ()),
                                  orthographic(half_w, half_h, 0.5f, box.sizes().y() + 1.5f));

  auto pixel = [&](double x, double z) {
    return cv::Point(static_cast<int>(std::lround((x - (centre.x() - half_w)) * ppm)),
                     static_cast<int>(std::lround((z - (centre.z() - half_h)) * ppm)));
  };
  auto ring = [&](const std::vector<Eigen::Vector2d>& r) {
    std::vector<cv::Point> out;
    for (const auto& p : r) out.push_back(pixel(p.x(), p.y()));
    return out;
  };
  cv::Mat fill = image.clone();
  for (const auto& polygon : walkable.polygons) {
    std::vector<std::vector<cv::Point>> rings{ring(polygon.outer)};
    for (const auto& hole : polygon.holes) rings.push_back(ring(hole));
    cv::fillPoly(fill, rings, kWalkableRgb, cv::LINE_AA);  // even-odd: holes stay clear
  }
  cv::addWeighted(fill, kWalkableShade, image, 1 - kWalkableShade, 0, image);
  for (const auto& polygon : walkable.polygons) {
    cv::polylines(image, ring(polygon.outer), true, kWalkableRgb, 1, cv::LINE_AA);
    for (const auto& hole : polygon.holes) cv::polylines(image, ring(hole), true, kWalkableRgb, 1, cv::LINE_AA);
  }
  std::vector<cv::Point> path;
  for (const auto& p : nodes.path) path.push_back(pixel(p.x(), p.z()));
  cv::polylines(image, path, false, kPathRgb, 2, cv::LINE_AA);
  const Eigen::Vector3d spawn = nodes.spawn.translation();
  const Eigen::Vector3d heading = nodes.spawn.linear() * -Eigen::Vector3d::UnitZ();
  const cv::Point s = pixel(spawn.x(), spawn.z());
  cv::arrowedLine(image, s, pixel(spawn.x() + heading.x(), spawn.z() + heading.z()), kSpawnRgb, 2, cv::LINE_AA);
  cv::circle(image, s, 5, kSpawnRgb, cv::FILLED, cv::LINE_AA);
  return image;
}

}  // namespace valerant
