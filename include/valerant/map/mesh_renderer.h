#pragma once
// Quick-look pictures of a surface mesh in the asset frame (map_frame.h), rendered in
// software through OSMesa (Mesa's offscreen rasteriser, as for the engine world; no
// display or GPU needed): an orbit of perspective views around the map and a top-down
// orthographic overview with the walkable area, the path and the spawn drawn on it.
// Vertex colours are shaded by a fixed light from above (|n.l|, so either side of a
// surface is lit) to show shape and brightened toward a mid-grey median (game lighting
// is dark); both pictures cut away geometry higher than exports.render_cut_eye_heights
// over its floor, else ceilings hide the map.
#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/map/mesh_exports.h"
#include "valerant/map/surface_mesh.h"
#include "valerant/map/walkable_area.h"

namespace valerant {

// One OSMesa context of a fixed size; use from one thread at a time.
class MeshRenderer {
 public:
  MeshRenderer(int width, int height);
  ~MeshRenderer();
  MeshRenderer(const MeshRenderer&) = delete;
  MeshRenderer& operator=(const MeshRenderer&) = delete;

  // `view`: asset frame to OpenGL eye coordinates; `projection`: eye to clip. RGB.
  // A size beyond the rasteriser's limit (GL_MAX_VIEWPORT_DIMS) is an InputError.
  cv::Mat render(const SurfaceMesh& mesh, const Eigen::Matrix4f& view, const Eigen::Matrix4f& projection);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// exports.orbit_views RGB views around the mesh's bounding box, evenly spaced in
// azimuth, starting behind the spawn. Empty for an empty mesh.
std::vector<cv::Mat> renderOrbit(const SurfaceMesh& mesh, const ExportConfig& config);

// Top-down RGB picture, -Z (the spawn's heading) up, +X right, at
// exports.overview_pixels_per_metre, or smaller where that would make a side longer
// than exports.overview_max_side_px: the mesh, the walkable area shaded green with its
// outline, the path in yellow and the spawn in blue. Empty for an empty mesh.
cv::Mat renderOverview(const SurfaceMesh& mesh, const WalkableArea& walkable, const AssetNodes& nodes,
                       const ExportConfig& config);

}  // namespace valerant
