#pragma once
// One training shard: a zip of JPEG colour frames, log16 depth PNGs (log_depth_code.h),
// frames.csv (one row per frame: where it came from, its pose and its key) and
// meta.json (camera, depth code, seed, split, maps). Compact enough to send to the GPU
// host (a 128 x 96 frame is about 10 KB) and read by learn/valerant_learn/shards.py
// without ROS. The same seed gives the same bytes: entries carry a fixed time stamp.
// The zip is written under a temporary name and renamed into place when complete, so
// a shard under its final name is always whole.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "valerant/common/camera.h"

namespace cv {
class Mat;
}

namespace valerant::dataset {

// Where a frame came from and how the camera stood.
struct FrameRecord {
  std::string map;
  int spawn = -1;       // spawn index the sequence started at; -1 = a random floor cell
  int sequence = 0;     // sequence number within the shard's run (unique per map)
  int step = 0;         // frame index within the sequence (0 = its start)
  std::string kind;     // rollout (a paper candidate), rotate (turn in place), walk (random keys)
  std::string key;      // the frame's keys (w, jw, l, ...; empty for a start frame)
  Eigen::Vector3d eye_m = Eigen::Vector3d::Zero();  // eye in the BSP frame, metres
  double yaw_deg = 0, pitch_deg = 0;
  bool in_solid = false;  // the pose penetrates the world (CameraKinematics::inSolid)
};

struct ShardMeta {
  CameraIntrinsics intrinsics;
  uint64_t seed = 0;
  std::string split;  // train | evaluation (config/map_sets.yaml)
  double eye_height_m = 0;
  int jpeg_quality = 90;
  double texture_shuffle = 0;  // valerant_dataset --texture-shuffle (0: the maps' own textures)
};

class ShardWriter {
 public:
  // Throws InputError naming `path` when it exists already or its folder is missing.
  ShardWriter(std::string path, ShardMeta meta);
  // `rgb`: CV_8UC3 RGB; `depth_m`: CV_32F metres, NaN = sky; both of the meta's size.
  void add(const FrameRecord& record, const cv::Mat& rgb, const cv::Mat& depth_m);
  size_t frames() const { return records_.size(); }
  size_t bytes() const { return bytes_; }  // encoded images so far
  // Writes the zip (temporary name, checked, synced, renamed). Throws InputError naming
  // the file on any failure, leaving no file under the final name.
  void finish();

 private:
  struct Entry {
    std::string name;
    std::vector<unsigned char> data;
    bool compress = false;
  };
  std::string path_;
  ShardMeta meta_;
  std::vector<FrameRecord> records_;
  std::vector<Entry> entries_;
  size_t bytes_ = 0;
};

}  // namespace valerant::dataset
