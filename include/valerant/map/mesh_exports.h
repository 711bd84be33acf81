#pragma once
// Surface-mesh files a game engine or DCC tool loads, in the asset frame (map_frame.h:
// metres, Y up): Wavefront OBJ with vertex colours ("v x y z r g b", read by Blender,
// MeshLab, tinyobjloader) and binary glTF 2.0 (.glb, written with tinygltf). Each holds
// three named objects: "map" (the triangles), "spawn" (the player's feet at the start,
// looking along -Z) and "path" (the feet of the committed camera, one vertex per
// committed frame, as a line strip). Writers never overwrite unless asked and throw
// InputError naming the file.
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "valerant/map/map_frame.h"
#include "valerant/map/surface_mesh.h"

namespace valerant {

struct AssetNodes {
  Eigen::Isometry3d spawn = Eigen::Isometry3d::Identity();  // asset frame
  std::vector<Eigen::Vector3f> path;                        // asset frame
};

// `frame` is recorded in the file (scale and where it came from).
void writeMeshObj(const std::string& path, const SurfaceMesh& mesh, const AssetNodes& nodes, const MapFrame& frame,
                  bool overwrite);
void writeMeshGlb(const std::string& path, const SurfaceMesh& mesh, const AssetNodes& nodes, const MapFrame& frame,
                  bool overwrite);

}  // namespace valerant
