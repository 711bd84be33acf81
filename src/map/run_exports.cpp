#include "valerant/map/run_exports.h"

#include <octomap/ColorOcTree.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <future>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <utility>

#include "valerant/common/contact_sheet.h"
#include "valerant/common/error.h"
#include "valerant/common/joined.h"
#include "valerant/common/output_file.h"
#include "valerant/map/map_exports.h"
#include "valerant/map/mesh_exports.h"
#include "valerant/map/mesh_renderer.h"
#include "valerant/map/surface_mesh.h"
#include "valerant/map/walkable_area.h"

namespace valerant {
namespace {

// Every format and its files, in the order of run_exports.h.
const std::vector<std::pair<std::string, std::vector<std::string>>>& formatTable() {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> table = {
      {"ply", {"map.ply"}},         {"pcd", {"map.pcd"}},  {"bt", {"map.bt"}},
      {"grid", {"grid.pgm", "grid.yaml"}}, {"obj", {"mesh.obj"}}, {"glb", {"mesh.glb"}},
      {"walkable", {"walkable.json"}}, {"png", {"overview.png", "orbit.png"}}};
  return table;
}

const std::vector<std::string>& filesOf(const std::string& format) {
  for (const auto& [name, files] : formatTable())
    if (name == format) return files;
  throw InputError("export format '" + format + "'", "unknown");
}

void writeRgbPng(const std::string& path, const cv::Mat& rgb) {
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  writeImageAtomically(path, bgr);
}

// The spawn (feet of the first committed camera, turned about Y to its heading) and the
// feet of every committed camera, in the asset frame.
AssetNodes assetNodes(const RunMap& run) {
  AssetNodes nodes;
  if (run.trajectory.empty()) return nodes;
  const Eigen::Affine3d to_asset = run.frame.mapToAsset();
  auto feet = [&](const Eigen::Isometry3d& camera) {
    return to_asset * (camera.translation() - run.frame.eye_height * run.frame.up);
  };
  for (const auto& pose : run.trajectory) nodes.path.push_back(feet(pose).cast<float>());
  const Eigen::Vector3d heading = to_asset.linear() * run.trajectory.front().linear().col(2);  // optical axis
  nodes.spawn.translation() = feet(run.trajectory.front());
  nodes.spawn.linear() = Eigen::AngleAxisd(std::atan2(-heading.x(), -heading.z()), Eigen::Vector3d::UnitY()).matrix();
  return nodes;
}

}  // namespace

const std::vector<std::string>& exportFormats() {
  static const std::vector<std::string> formats = [] {
    std::vector<std::string> names;
    for (const auto& entry : formatTable()) names.push_back(entry.first);
    return names;
  }();
  return formats;
}

std::vector<std::string> parseFormats(const std::string& comma_separated) {
  std::vector<std::string> formats;
  std::istringstream in(comma_separated);
  for (std::string name; std::getline(in, name, ',');) {
    if (!std::count(exportFormats().begin(), exportFormats().end(), name))
      throw InputError("--formats " + comma_separated, "unknown format '" + name + "' (known: " +
                                                         joined(exportFormats()) + ")");
    if (std::count(formats.begin(), formats.end(), name))
      throw InputError("--formats " + comma_separated, "'" + name + "' given twice");
    formats.push_back(name);
  }
  if (formats.empty()) throw InputError("--formats " + comma_separated, "names no format");
  return formats;
}

std::vector<std::string> exportFiles(const std::vector<std::string>& formats) {
  std::vector<std::string> files;
  for (const auto& f : formats) {
    const auto& names = filesOf(f);
    files.insert(files.end(), names.begin(), names.end());
  }
  return files;
}

nlohmann::json exportRunMap(const RunMap& run, const std::vector<std::string>& formats, const std::string& out,
                            bool overwrite) {
  auto path = [&](const std::string& name) { return (std::filesystem::path(out) / name).string(); };
  for (const auto& name : exportFiles(formats)) requireWritable(path(name), overwrite);
  auto wanted = [&](const char* format) { return std::count(formats.begin(), formats.end(), format) > 0; };

  const Config& config = run.config;
  const double kappa = run.frame.eye_height;
  const double voxel = config.map.voxel_eye_heights * kappa;
  const std::vector<FusedPoint> cloud = run.map.voxelCloud(voxel);
  nlohmann::json files = nlohmann::json::array(), skipped = nlohmann::json::object();
  auto wrote = [&](const char* format) {
    for (const auto& name : filesOf(format)) files.push_back(name);
  };

  auto cloudFormat = [&](const char* format, const std::function<void()>& write) {
    if (!wanted(format)) return;
    if (cloud.empty()) {
      skipped[format] = "the map has no points";
      return;
    }
    write();
    wrote(format);
  };
  // The surface mesh (the triangulation: most of the exports' time) is made beside the
  // cloud formats, the octree and the grids, on the machine's other core; they only read
  // the map. get() below rethrows its error; an error before it waits for it (the
  // future's destructor).
  struct Meshed {
    SurfaceMesh mesh;
    double leaf = 0;
  };
  std::future<Meshed> meshing;
  if (wanted("obj") || wanted("glb") || wanted("png"))
    meshing = std::async(std::launch::async, [&run, &config, points = cloud, voxel]() mutable {
      std::vector<Eigen::Vector3d> viewpoints;
      for (const auto& kf : run.map.keyframes()) viewpoints.push_back(kf->camera_to_map.translation());
      MeshCloud mesh_cloud = meshCloud(std::move(points), voxel, static_cast<size_t>(config.exports.mesh_max_points),
                                       [&](double leaf) { return run.map.voxelCloud(leaf); });
      return Meshed{transformMesh(triangulateCloud(mesh_cloud.points, viewpoints,
                                                   meshParams(config.exports, mesh_cloud.leaf)),
                                  run.frame.mapToAsset()),
                    mesh_cloud.leaf};
    });
  cloudFormat("ply", [&] { writeCloudPly(path("map.ply"), cloud, overwrite); });
  cloudFormat("pcd", [&] { writeCloudPcd(path("map.pcd"), cloud, overwrite); });
  cloudFormat("bt", [&] {
    writeOctreeBt(path("map.bt"), *run.map.octree(config.map.octree_eye_heights * kappa), overwrite);
  });

  if (wanted("grid")) {
    writeFloorGrid(path("grid"), run.floorGrid(config.map.grid_cell_fraction), overwrite);
    wrote("grid");
  }

  const WalkableArea walkable =
      walkableArea(run.floorGrid(config.exports.walkable_cell_fraction), run.frame,
                   {config.collision.body_radius * kappa, config.exports.walkable_close_cells,
                    config.exports.walkable_min_area_m2});
  if (wanted("walkable")) {
    writeWalkableJson(path("walkable.json"), walkable, overwrite);
    wrote("walkable");
  }

  nlohmann::json result = {{"map_points", cloud.size()},
                            {"walkable",
                             {{"polygons", walkable.polygons.size()},
                              {"area_m2", walkable.areaSquareMetres()},
                              {"cell_size_m", walkable.cell_size_m},
                              {"clearance_m", walkable.clearance_m}}},
                            {"map_frame", toJson(run.frame)}};
  if (meshing.valid()) {
    const Meshed meshed = meshing.get();
    const SurfaceMesh& mesh = meshed.mesh;
    result["mesh"] = {{"vertices", mesh.positions.size()},
                      {"triangles", mesh.triangles.size()},
                      {"leaf_m", meshed.leaf * run.frame.metres_per_unit}};
    const AssetNodes nodes = assetNodes(run);
    auto meshFormat = [&](const char* format, const std::function<void()>& write) {
      if (!wanted(format)) return;
      if (mesh.triangles.empty()) {
        skipped[format] = "the map has too few points for a surface";
        return;
      }
      write();
      wrote(format);
    };
    meshFormat("obj", [&] { writeMeshObj(path("mesh.obj"), mesh, nodes, run.frame, overwrite); });
    meshFormat("glb", [&] { writeMeshGlb(path("mesh.glb"), mesh, nodes, run.frame, overwrite); });
    meshFormat("png", [&] {
      writeRgbPng(path("overview.png"), renderOverview(mesh, walkable, nodes, config.exports));
      const auto views = renderOrbit(mesh, config.exports);
      writeRgbPng(path("orbit.png"), makeContactSheet(views, "orbit", static_cast<int>(views.size())));
    });
  }
  result["files"] = files;
  result["skipped"] = skipped;
  return result;
}

}  // namespace valerant
