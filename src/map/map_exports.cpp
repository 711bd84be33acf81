#include "valerant/map/map_exports.h"

#define PCL_NO_PRECOMPILE
#include <octomap/ColorOcTree.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

#include <filesystem>
#include <sstream>

#include "valerant/common/error.h"
#include "valerant/common/output_file.h"

namespace valerant {
namespace {

struct PointXYZRGBConfidence {
  PCL_ADD_POINT4D;
  PCL_ADD_RGB;
  float confidence;
  PCL_MAKE_ALIGNED_OPERATOR_NEW
};

}  // namespace
}  // namespace valerant

POINT_CLOUD_REGISTER_POINT_STRUCT(valerant::PointXYZRGBConfidence,
                                  (float, x, x)(float, y, y)(float, z, z)(float, rgb, rgb)(float, confidence,
                                                                                           confidence))

namespace valerant {
namespace {

pcl::PointCloud<PointXYZRGBConfidence> toPcl(const std::vector<FusedPoint>& points) {
  pcl::PointCloud<PointXYZRGBConfidence> cloud;
  cloud.reserve(points.size());
  for (const auto& p : points) {
    PointXYZRGBConfidence q;
    q.x = p.position.x(), q.y = p.position.y(), q.z = p.position.z();
    q.r = p.rgb[0], q.g = p.rgb[1], q.b = p.rgb[2], q.a = 255;
    q.confidence = p.confidence;
    cloud.push_back(q);
  }
  return cloud;
}

}  // namespace

void writeCloudPly(const std::string& path, const std::vector<FusedPoint>& points, bool overwrite) {
  requireWritable(path, overwrite);
  if (points.empty()) throw InputError(path, "refusing to write an empty point cloud");
  const auto cloud = toPcl(points);
  writeThroughTemporary(path, "PCL's PLY writer",
                        [&](const std::string& temporary) { return pcl::io::savePLYFileBinary(temporary, cloud) == 0; });
}

void writeCloudPcd(const std::string& path, const std::vector<FusedPoint>& points, bool overwrite) {
  requireWritable(path, overwrite);
  if (points.empty()) throw InputError(path, "refusing to write an empty point cloud");
  const auto cloud = toPcl(points);
  writeThroughTemporary(path, "PCL's PCD writer",
                        [&](const std::string& temporary) { return pcl::io::savePCDFileBinary(temporary, cloud) == 0; });
}

void writeOctreeBt(const std::string& path, const octomap::ColorOcTree& tree, bool overwrite) {
  requireWritable(path, overwrite);
  // writeBinary thresholds and prunes the tree it writes, which would change a live
  // tree's later updates (live_map.h); a copy is written instead.
  octomap::ColorOcTree copy(tree);
  std::ostringstream bytes;
  if (!copy.writeBinary(bytes)) throw InputError(path, "OctoMap could not write the .bt file");
  writeFileAtomically(path, bytes.str());
}

void writeFloorGrid(const std::string& stem, const FloorGrid& grid, bool overwrite) {
  const std::string pgm = stem + ".pgm", yaml = stem + ".yaml";
  requireWritable(pgm, overwrite);
  requireWritable(yaml, overwrite);
  cv::Mat image(grid.height, grid.width, CV_8UC1);
  for (int row = 0; row < grid.height; ++row) {
    for (int col = 0; col < grid.width; ++col) {
      const int8_t v = grid.cells[static_cast<size_t>(row) * grid.width + col];
      // map_server's image has its first row at the top, i.e. the highest v.
      image.at<uint8_t>(grid.height - 1 - row, col) = v < 0 ? 205 : (v >= 50 ? 0 : 254);
    }
  }
  writeImageAtomically(pgm, image);
  std::ostringstream out;
  out << "image: " << std::filesystem::path(pgm).filename().string() << "\n"
      << "resolution: " << grid.resolution << "\n"
      << "origin: [" << grid.origin.x() << ", " << grid.origin.y() << ", 0.0]\n"
      << "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
  writeFileAtomically(yaml, out.str());
}

}  // namespace valerant
