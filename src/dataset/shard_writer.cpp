#include "valerant/dataset/shard_writer.h"

#include <fcntl.h>
#include <unistd.h>
#include <zip.h>

#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <sstream>

#include "valerant/common/error.h"
#include "valerant/common/output_file.h"
#include "valerant/dataset/log_depth_code.h"
#include "valerant/world/quake3/units.h"

namespace valerant::dataset {
namespace {

constexpr time_t kEntryTime = 946684800;  // 2000-01-01: fixed, so a seed gives the same bytes

std::string frameName(const char* folder, size_t index, const char* extension) {
  char name[48];
  std::snprintf(name, sizeof(name), "%s/%06zu.%s", folder, index, extension);
  return name;
}

std::vector<unsigned char> bytesOf(const std::string& text) { return {text.begin(), text.end()}; }

// CSV field: keys and map names never hold commas or quotes; refuse anything that would.
const std::string& csvField(const std::string& s) {
  if (s.find_first_of(",\"\n") != std::string::npos) throw InputError("shard field '" + s + "'", "holds a CSV separator");
  return s;
}

void fsyncFile(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0 || ::fsync(fd) != 0) {
    if (fd >= 0) ::close(fd);
    throw InputError(path, "cannot sync to disk");
  }
  ::close(fd);
}

}  // namespace

ShardWriter::ShardWriter(std::string path, ShardMeta meta) : path_(std::move(path)), meta_(std::move(meta)) {
  requireWritable(path_, false);
}

void ShardWriter::add(const FrameRecord& record, const cv::Mat& rgb, const cv::Mat& depth_m) {
  const cv::Size size(meta_.intrinsics.width, meta_.intrinsics.height);
  if (rgb.type() != CV_8UC3 || rgb.size() != size || depth_m.type() != CV_32F || depth_m.size() != size)
    throw InputError(path_ + " frame " + std::to_string(records_.size()), "colour or depth of the wrong type or size");
  const size_t index = records_.size();
  Entry colour{frameName("rgb", index, "jpg"), {}, false};
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  if (!cv::imencode(".jpg", bgr, colour.data, {cv::IMWRITE_JPEG_QUALITY, meta_.jpeg_quality}))
    throw InputError(colour.name, "JPEG encoding failed");
  Entry depth{frameName("depth", index, "png"), {}, false};
  if (!cv::imencode(".png", encodeLogDepthImage(depth_m), depth.data, {cv::IMWRITE_PNG_COMPRESSION, 9}))
    throw InputError(depth.name, "PNG encoding failed");
  bytes_ += colour.data.size() + depth.data.size();
  entries_.push_back(std::move(colour));
  entries_.push_back(std::move(depth));
  records_.push_back(record);
}

void ShardWriter::finish() {
  std::ostringstream csv;
  csv << "index,map,spawn,sequence,step,kind,key,x,y,z,yaw_deg,pitch_deg,in_solid\n" << std::setprecision(6)
      << std::fixed;
  std::set<std::string> maps;
  for (size_t i = 0; i < records_.size(); ++i) {
    const FrameRecord& r = records_[i];
    csv << i << ',' << csvField(r.map) << ',' << r.spawn << ',' << r.sequence << ',' << r.step << ','
        << csvField(r.kind) << ',' << csvField(r.key) << ',' << r.eye_m.x() << ',' << r.eye_m.y() << ','
        << r.eye_m.z() << ',' << r.yaw_deg << ',' << r.pitch_deg << ',' << (r.in_solid ? 1 : 0) << '\n';
    maps.insert(r.map);
  }
  const CameraIntrinsics& k = meta_.intrinsics;
  const nlohmann::json meta = {{"format", "valerant-dataset-1"},
                               {"width", k.width},
                               {"height", k.height},
                               {"fx", k.fx},
                               {"fy", k.fy},
                               {"cx", k.cx},
                               {"cy", k.cy},
                               {"depth_encoding", "log16"},
                               {"depth_min_m", kMinDepthM},
                               {"depth_max_m", kMaxDepthM},
                               {"seed", meta_.seed},
                               {"split", meta_.split},
                               {"maps", std::vector<std::string>(maps.begin(), maps.end())},
                               {"frames", records_.size()},
                               {"units_per_metre", quake3::kUnitsPerMetre},
                               {"eye_height_m", meta_.eye_height_m},
                               {"texture_shuffle", meta_.texture_shuffle}};
  std::vector<Entry> all;
  all.push_back({"meta.json", bytesOf(meta.dump(1) + "\n"), true});
  all.push_back({"frames.csv", bytesOf(csv.str()), true});

  const std::string tmp = path_ + ".partial";
  std::filesystem::remove(tmp);
  int error = 0;
  zip_t* zip = zip_open(tmp.c_str(), ZIP_CREATE | ZIP_EXCL, &error);
  if (!zip) throw InputError(tmp, "cannot create zip (libzip error " + std::to_string(error) + ")");
  auto fail = [&](const std::string& what) {
    const std::string detail = zip_strerror(zip);
    zip_discard(zip);
    std::filesystem::remove(tmp);
    throw InputError(tmp, what + ": " + detail);
  };
  auto addEntry = [&](const Entry& e) {
    zip_source_t* source = zip_source_buffer(zip, e.data.data(), e.data.size(), 0);
    if (!source) fail("cannot add " + e.name);
    const zip_int64_t index = zip_file_add(zip, e.name.c_str(), source, ZIP_FL_ENC_UTF_8);
    if (index < 0) {
      zip_source_free(source);
      fail("cannot add " + e.name);
    }
    // JPEG and PNG are compressed already: stored, they cost no time to read.
    if (zip_set_file_compression(zip, static_cast<zip_uint64_t>(index), e.compress ? ZIP_CM_DEFLATE : ZIP_CM_STORE,
                                 0) != 0 ||
        zip_file_set_mtime(zip, static_cast<zip_uint64_t>(index), kEntryTime, 0) != 0)
      fail("cannot set up " + e.name);
  };
  for (const Entry& e : all) addEntry(e);
  for (const Entry& e : entries_) addEntry(e);
  if (zip_close(zip) != 0) fail("cannot write");  // a full disk ends here
  fsyncFile(tmp);
  std::error_code ec;
  std::filesystem::rename(tmp, path_, ec);
  if (ec) {
    std::filesystem::remove(tmp);
    throw InputError(path_, "cannot rename the finished shard into place: " + ec.message());
  }
}

}  // namespace valerant::dataset
