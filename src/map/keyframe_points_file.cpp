#include "valerant/map/keyframe_points_file.h"

#define PCL_NO_PRECOMPILE
#include <pcl/common/io.h>
#include <pcl/console/print.h>
#include <pcl/conversions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <filesystem>

#include "valerant/common/error.h"
#include "valerant/common/output_file.h"

namespace valerant {
namespace {

struct KeyframePoint {
  PCL_ADD_POINT4D;
  PCL_ADD_RGB;
  float confidence;
  float h;
  std::uint32_t keyframe;
  PCL_MAKE_ALIGNED_OPERATOR_NEW
};

}  // namespace
}  // namespace valerant

POINT_CLOUD_REGISTER_POINT_STRUCT(valerant::KeyframePoint,
                                  (float, x, x)(float, y, y)(float, z, z)(float, rgb, rgb)(float, confidence,
                                                                                           confidence)(
                                      float, h, h)(std::uint32_t, keyframe, keyframe))

namespace valerant {

size_t writeKeyframePoints(const std::string& path, const std::vector<std::shared_ptr<const FusedKeyframe>>& keyframes,
                           size_t first, size_t end) {
  pcl::PointCloud<KeyframePoint> cloud;
  for (size_t k = first; k < end; ++k) {
    for (const auto& p : keyframes[k]->points) {
      KeyframePoint q;
      q.x = p.position.x(), q.y = p.position.y(), q.z = p.position.z();
      q.r = p.rgb[0], q.g = p.rgb[1], q.b = p.rgb[2], q.a = 255;
      q.confidence = p.confidence;
      q.h = p.h;
      q.keyframe = static_cast<std::uint32_t>(k);
      cloud.push_back(q);
    }
  }
  // PCL refuses to write a cloud without points; an empty map still gets a valid file.
  if (cloud.empty()) {
    writeFileAtomically(path,
                        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
                        "FIELDS x y z rgb confidence h keyframe\nSIZE 4 4 4 4 4 4 4\nTYPE F F F F F F U\n"
                        "COUNT 1 1 1 1 1 1 1\nWIDTH 0\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 0\nDATA ascii\n");
  } else {
    writeThroughTemporary(path, "PCL's PCD writer", [&](const std::string& temporary) {
      return pcl::io::savePCDFileBinaryCompressed(temporary, cloud) == 0;
    });
  }
  return cloud.size();
}

size_t readKeyframePoints(const std::string& path, const std::vector<std::shared_ptr<FusedKeyframe>>& keyframes) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path, "missing (not a finished valerant_explore run?)");
  pcl::PCLPointCloud2 blob;
  // PCL reports its own parse errors on the console; ours names the file in one line.
  const auto verbosity = pcl::console::getVerbosityLevel();
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  const int status = pcl::io::loadPCDFile(path, blob);
  pcl::console::setVerbosityLevel(verbosity);
  if (status != 0) throw InputError(path, "PCL cannot read it (truncated or not a PCD file)");
  for (const char* name : {"x", "y", "z", "rgb", "confidence", "h", "keyframe"})
    if (pcl::getFieldIndex(blob, name) < 0) throw InputError(path, std::string("has no field '") + name + "'");
  pcl::PointCloud<KeyframePoint> cloud;
  pcl::fromPCLPointCloud2(blob, cloud);
  for (const auto& q : cloud) {
    if (q.keyframe >= keyframes.size())
      throw InputError(path, "a point names keyframe " + std::to_string(q.keyframe) + ", beyond the " +
                                 std::to_string(keyframes.size()) + " keyframe poses");
    keyframes[q.keyframe]->points.push_back({q.getVector3fMap(), {q.r, q.g, q.b}, q.confidence, q.h});
  }
  return cloud.size();
}

}  // namespace valerant
