#pragma once
// Files of a fused map, each in a format a common tool reads: PLY and PCD (PCL), OctoMap
// .bt, and the ROS map_server PGM + YAML pair. Every writer refuses to overwrite an
// existing file unless `overwrite` is set, and throws InputError naming the file.
#include <string>
#include <vector>

#include "valerant/map/map_fusion.h"

namespace octomap {
class ColorOcTree;
}

namespace valerant {

// Binary PLY: x y z (float) red green blue (uchar) confidence (float).
void writeCloudPly(const std::string& path, const std::vector<FusedPoint>& points, bool overwrite);
// Binary PCD with the same fields.
void writeCloudPcd(const std::string& path, const std::vector<FusedPoint>& points, bool overwrite);
// OctoMap binary occupancy (.bt).
void writeOctreeBt(const std::string& path, const octomap::ColorOcTree& tree, bool overwrite);
// `stem`.pgm + `stem`.yaml in map_server format (free 254, occupied 0, unknown 205).
void writeFloorGrid(const std::string& stem, const FloorGrid& grid, bool overwrite);

}  // namespace valerant
