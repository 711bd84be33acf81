#pragma once
// Every file a run's map is exported to, by format name: one code path for
// valerant_explore (all formats, into its run directory) and valerant_export (any
// subset, from a run directory).
//   ply       map.ply                    voxel cloud (PCL)              SLAM map frame, map units
//   pcd       map.pcd                    the same
//   bt        map.bt                     OctoMap occupancy
//   grid      grid.pgm + grid.yaml       map_server floor grid          anchor floor, map units
//   obj       mesh.obj                   surface mesh (OBJ)             asset frame: metres, Y up
//   glb       mesh.glb                   surface mesh (glTF 2.0 binary)   (map_frame.h)
//   walkable  walkable.json              walkable polygons
//   png       overview.png + orbit.png   top-down view, orbit contact sheet
// The cloud, octree and grid stay in the SLAM map frame that ROS tools (rviz, map_server)
// show next to the trajectory; the game-engine assets are in metres, Y up.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "valerant/map/run_map.h"

namespace valerant {

// All format names, in the order above.
const std::vector<std::string>& exportFormats();
// "ply,obj" -> {"ply", "obj"}; throws InputError naming an unknown or repeated format.
std::vector<std::string> parseFormats(const std::string& comma_separated);
// Files the formats write, in order.
std::vector<std::string> exportFiles(const std::vector<std::string>& formats);

// Writes `formats` of `run` into the directory `out`. Every target is checked first,
// so nothing is written when one exists and `overwrite` is false. A format needing
// points, or triangles, that the map lacks is skipped with the reason. Returns
// {"files", "skipped", "map_points", "mesh", "walkable", "map_frame"} for a report.
// The mesh is made on a second thread, beside the other formats.
nlohmann::json exportRunMap(const RunMap& run, const std::vector<std::string>& formats, const std::string& out,
                            bool overwrite);

}  // namespace valerant
