#include "valerant/ros/conversions.h"

#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstring>

#include "valerant/common/error.h"

namespace valerant::bridge {
namespace {

// The rotation of a received pose must be orthonormal to this tolerance.
constexpr double kRotationTolerance = 1e-6;

// zlib strategies measured on 320x240 OpenArena frames (CPU time per frame): colour
// (noisy textures, which PNG's row filters already decorrelate) compresses best with
// Huffman coding alone, 86 KB in 3.6 ms against 101 KB in 4.5 ms for the default at
// level 1 and 96 KB in 7.7 ms at level 3; depth's float bytes (flat floors and walls)
// with run-length matches, 9.8 KB in 2.0 ms against 13.6 KB in 2.2 ms. The world model
// server encodes every frame of every rollout on its per-frame path.
constexpr int kPngLevel = 1;

// A depth image travels as the bytes of its floats; the format names them little-endian.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "kDepthPngFormat assumes a little-endian host");

std::vector<uint8_t> encodePng(const cv::Mat& image, int strategy, const std::string& what) {
  std::vector<uint8_t> bytes;
  if (!cv::imencode(".png", image, bytes, {cv::IMWRITE_PNG_COMPRESSION, kPngLevel, cv::IMWRITE_PNG_STRATEGY, strategy}))
    throw InputError(what, "PNG encoding failed");
  return bytes;
}

cv::Mat decodePng(const std::vector<uint8_t>& bytes, int expected_type, const std::string& format) {
  cv::Mat decoded;
  try {
    decoded = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception&) {
    // OpenCV throws for some damaged PNGs and returns an empty Mat for others.
  }
  if (decoded.empty() || decoded.type() != expected_type)
    throw InputError("compressed image (" + format + ")", "its data is no PNG of that format");
  return decoded;
}

float packRgb(const std::array<uint8_t, 3>& rgb) {
  const uint32_t packed = (uint32_t{rgb[0]} << 16) | (uint32_t{rgb[1]} << 8) | rgb[2];
  float f;
  std::memcpy(&f, &packed, sizeof f);
  return f;
}

std::array<uint8_t, 3> unpackRgb(float f) {
  uint32_t packed;
  std::memcpy(&packed, &f, sizeof packed);
  return {static_cast<uint8_t>(packed >> 16), static_cast<uint8_t>(packed >> 8), static_cast<uint8_t>(packed)};
}

sensor_msgs::PointCloud2 makeCloud(const std::string& frame_id, size_t n, bool with_h) {
  sensor_msgs::PointCloud2 msg;
  msg.header.frame_id = frame_id;
  sensor_msgs::PointCloud2Modifier modifier(msg);
  if (with_h)
    modifier.setPointCloud2Fields(6, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32,
                                  "z", 1, sensor_msgs::PointField::FLOAT32, "rgb", 1, sensor_msgs::PointField::FLOAT32,
                                  "confidence", 1, sensor_msgs::PointField::FLOAT32, "h", 1,
                                  sensor_msgs::PointField::FLOAT32);
  else
    modifier.setPointCloud2Fields(5, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32,
                                  "z", 1, sensor_msgs::PointField::FLOAT32, "rgb", 1, sensor_msgs::PointField::FLOAT32,
                                  "confidence", 1, sensor_msgs::PointField::FLOAT32);
  modifier.resize(n);
  return msg;
}

bool hasField(const sensor_msgs::PointCloud2& msg, const std::string& name) {
  for (const auto& f : msg.fields)
    if (f.name == name && f.datatype == sensor_msgs::PointField::FLOAT32) return true;
  return false;
}

void checkCloud(const sensor_msgs::PointCloud2& msg, bool with_h) {
  for (const char* name : {"x", "y", "z", "rgb", "confidence"})
    if (!hasField(msg, name)) throw InputError("point cloud", std::string("has no float32 field '") + name + "'");
  if (with_h && !hasField(msg, "h")) throw InputError("point cloud", "has no float32 field 'h'");
  if (msg.data.size() < static_cast<size_t>(msg.row_step) * msg.height ||
      static_cast<size_t>(msg.point_step) * msg.width > msg.row_step)
    throw InputError("point cloud", "data shorter than its declared size");
}

}  // namespace

valerant::Isometry toMsg(const Eigen::Isometry3d& pose) {
  valerant::Isometry msg;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) msg.m[r * 4 + c] = pose.matrix()(r, c);
  return msg;
}

Eigen::Isometry3d fromMsg(const valerant::Isometry& msg) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) pose.matrix()(r, c) = msg.m[r * 4 + c];
  if (!pose.matrix().allFinite()) throw InputError("pose", "holds NaN or infinity");
  const Eigen::Matrix3d rtr = pose.linear().transpose() * pose.linear();
  if (!rtr.isApprox(Eigen::Matrix3d::Identity(), kRotationTolerance))
    throw InputError("pose", "its rotation is not orthonormal");
  return pose;
}

geometry_msgs::Pose toPoseMsg(const Eigen::Isometry3d& pose) {
  geometry_msgs::Pose msg;
  msg.position.x = pose.translation().x();
  msg.position.y = pose.translation().y();
  msg.position.z = pose.translation().z();
  const Eigen::Quaterniond q(pose.linear());
  msg.orientation.x = q.x();
  msg.orientation.y = q.y();
  msg.orientation.z = q.z();
  msg.orientation.w = q.w();
  return msg;
}

sensor_msgs::Image toImageMsg(const cv::Mat& image) {
  sensor_msgs::Image msg;
  if (image.empty()) return msg;
  if (image.type() == CV_8UC3) {
    msg.encoding = sensor_msgs::image_encodings::RGB8;
  } else if (image.type() == CV_32FC1) {
    msg.encoding = sensor_msgs::image_encodings::TYPE_32FC1;
  } else {
    throw InputError("image", "type " + std::to_string(image.type()) + " has no protocol encoding");
  }
  msg.height = image.rows;
  msg.width = image.cols;
  msg.step = static_cast<uint32_t>(image.cols * image.elemSize());
  msg.data.resize(static_cast<size_t>(msg.step) * msg.height);
  for (int r = 0; r < image.rows; ++r) std::memcpy(&msg.data[r * msg.step], image.ptr(r), msg.step);
  return msg;
}

cv::Mat fromImageMsg(const sensor_msgs::Image& msg) {
  if (msg.data.empty() && msg.width == 0) return {};
  int type;
  if (msg.encoding == sensor_msgs::image_encodings::RGB8) {
    type = CV_8UC3;
  } else if (msg.encoding == sensor_msgs::image_encodings::TYPE_32FC1) {
    type = CV_32FC1;
  } else {
    throw InputError("image encoding '" + msg.encoding + "'", "unsupported (rgb8 or 32FC1)");
  }
  cv::Mat image(msg.height, msg.width, type);
  const size_t row = msg.width * image.elemSize();
  if (msg.step < row || msg.data.size() < static_cast<size_t>(msg.step) * msg.height)
    throw InputError("image", "data shorter than its declared size");
  for (int r = 0; r < image.rows; ++r) std::memcpy(image.ptr(r), &msg.data[r * msg.step], row);
  return image;
}

const char* const kRgbPngFormat = "rgb8; png compressed bgr8";
const char* const kDepthPngFormat = "32FC1; png compressed rgba8 of the little-endian float bytes";

sensor_msgs::CompressedImage toCompressedImageMsg(const cv::Mat& image) {
  sensor_msgs::CompressedImage msg;
  if (image.empty()) return msg;
  if (image.type() == CV_8UC3) {
    // PNG viewers expect the colours in order: OpenCV's encoder reads BGR.
    cv::Mat bgr;
    cv::cvtColor(image, bgr, cv::COLOR_RGB2BGR);
    msg.format = kRgbPngFormat;
    msg.data = encodePng(bgr, cv::IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY, "rgb image");
  } else if (image.type() == CV_32FC1) {
    const cv::Mat floats = image.isContinuous() ? image : image.clone();
    msg.format = kDepthPngFormat;
    msg.data = encodePng(cv::Mat(floats.rows, floats.cols, CV_8UC4, floats.data), cv::IMWRITE_PNG_STRATEGY_RLE,
                         "depth image");
  } else {
    throw InputError("image", "type " + std::to_string(image.type()) + " has no compressed protocol encoding");
  }
  return msg;
}

cv::Mat fromCompressedImageMsg(const sensor_msgs::CompressedImage& msg) {
  if (msg.format.empty() && msg.data.empty()) return {};
  if (msg.format == kRgbPngFormat) {
    cv::Mat rgb;
    cv::cvtColor(decodePng(msg.data, CV_8UC3, msg.format), rgb, cv::COLOR_BGR2RGB);
    return rgb;
  }
  if (msg.format == kDepthPngFormat) {
    const cv::Mat bytes = decodePng(msg.data, CV_8UC4, msg.format);
    return cv::Mat(bytes.rows, bytes.cols, CV_32FC1, bytes.data).clone();
  }
  throw InputError("compressed image format '" + msg.format + "'",
                   std::string("unsupported ('") + kRgbPngFormat + "' or '" + kDepthPngFormat + "')");
}

sensor_msgs::PointCloud2 toCloudMsg(const std::vector<CloudPoint>& points, const std::string& frame_id) {
  sensor_msgs::PointCloud2 msg = makeCloud(frame_id, points.size(), false);
  sensor_msgs::PointCloud2Iterator<float> x(msg, "x"), y(msg, "y"), z(msg, "z"), rgb(msg, "rgb"), conf(msg, "confidence");
  for (const auto& p : points) {
    *x = p.position.x(), *y = p.position.y(), *z = p.position.z();
    *rgb = packRgb(p.rgb);
    *conf = p.confidence;
    ++x, ++y, ++z, ++rgb, ++conf;
  }
  return msg;
}

std::vector<CloudPoint> fromCloudMsg(const sensor_msgs::PointCloud2& msg) {
  std::vector<CloudPoint> points;
  if (msg.width * msg.height == 0) return points;
  checkCloud(msg, false);
  sensor_msgs::PointCloud2ConstIterator<float> x(msg, "x"), y(msg, "y"), z(msg, "z"), rgb(msg, "rgb"),
      conf(msg, "confidence");
  points.reserve(msg.width * msg.height);
  for (; x != x.end(); ++x, ++y, ++z, ++rgb, ++conf) points.push_back({{*x, *y, *z}, unpackRgb(*rgb), *conf});
  return points;
}

sensor_msgs::PointCloud2 toFusedCloudMsg(const std::vector<FusedPoint>& points, const std::string& frame_id) {
  sensor_msgs::PointCloud2 msg = makeCloud(frame_id, points.size(), true);
  sensor_msgs::PointCloud2Iterator<float> x(msg, "x"), y(msg, "y"), z(msg, "z"), rgb(msg, "rgb"),
      conf(msg, "confidence"), h(msg, "h");
  for (const auto& p : points) {
    *x = p.position.x(), *y = p.position.y(), *z = p.position.z();
    *rgb = packRgb(p.rgb);
    *conf = p.confidence;
    *h = p.h;
    ++x, ++y, ++z, ++rgb, ++conf, ++h;
  }
  return msg;
}

std::vector<FusedPoint> fromFusedCloudMsg(const sensor_msgs::PointCloud2& msg) {
  std::vector<FusedPoint> points;
  if (msg.width * msg.height == 0) return points;
  checkCloud(msg, true);
  sensor_msgs::PointCloud2ConstIterator<float> x(msg, "x"), y(msg, "y"), z(msg, "z"), rgb(msg, "rgb"),
      conf(msg, "confidence"), h(msg, "h");
  points.reserve(msg.width * msg.height);
  for (; x != x.end(); ++x, ++y, ++z, ++rgb, ++conf, ++h) points.push_back({{*x, *y, *z}, unpackRgb(*rgb), *conf, *h});
  return points;
}

valerant::Floor toMsg(const FloorPlane& floor, uint32_t frame) {
  valerant::Floor msg;
  msg.header.frame_id = "map";
  msg.keyframe = frame;
  msg.q.x = floor.q.x(), msg.q.y = floor.q.y(), msg.q.z = floor.q.z();
  msg.n.x = floor.n.x(), msg.n.y = floor.n.y(), msg.n.z = floor.n.z();
  msg.c.x = floor.c.x(), msg.c.y = floor.c.y(), msg.c.z = floor.c.z();
  msg.known = floor.known;
  msg.reliable = floor.reliable;
  msg.support = static_cast<uint32_t>(floor.support);
  return msg;
}

FloorPlane fromMsg(const valerant::Floor& msg) {
  FloorPlane f;
  f.q = {msg.q.x, msg.q.y, msg.q.z};
  f.n = {msg.n.x, msg.n.y, msg.n.z};
  f.c = {msg.c.x, msg.c.y, msg.c.z};
  f.known = msg.known;
  f.reliable = msg.reliable;
  f.support = static_cast<int>(msg.support);
  return f;
}

valerant::Verdict toMsg(const BranchVerdict& v, const std::vector<Eigen::Vector3d>& centres) {
  valerant::Verdict msg;
  msg.candidate = v.candidate;
  msg.rotation_only = v.rotation_only;
  msg.collision_pc = v.collision_pc;
  msg.collision_depth = v.collision_depth;
  msg.turn_in_contact = v.turn_in_contact;
  msg.ends_in_contact = v.ends_in_contact;
  msg.occupied_max = static_cast<uint32_t>(v.occupied_max);
  msg.min_near_ratio = v.min_near_ratio;
  msg.body_counts.assign(v.body_counts.begin(), v.body_counts.end());
  msg.start_occupied = static_cast<uint32_t>(std::max(0, v.start_occupied));
  msg.see_through_points = static_cast<uint32_t>(std::max(0, v.see_through_points));
  msg.slam_lost = v.slam_lost;
  msg.floor_unknown = v.floor_unknown;
  msg.enters_failed = v.enters_failed;
  msg.prefix_frames = static_cast<uint32_t>(std::max(0, v.prefix_frames));
  msg.c_new = v.c_new, msg.c_front = v.c_front, msg.coverage = v.coverage, msg.progress = v.progress;
  msg.goal = v.goal, msg.opening = v.opening;
  msg.short_unclear = v.short_unclear;
  msg.turns_back = v.turns_back;
  msg.rewound_before = v.rewound_before;
  msg.score = v.score;
  msg.admissible = v.admissible;
  msg.yielded = v.yielded;
  msg.reason = v.reason;
  for (const auto& c : centres) {
    geometry_msgs::Point p;
    p.x = c.x(), p.y = c.y(), p.z = c.z();
    msg.centres.push_back(p);
  }
  return msg;
}

BranchVerdict fromMsg(const valerant::Verdict& msg) {
  BranchVerdict v;
  v.candidate = msg.candidate;
  v.rotation_only = msg.rotation_only;
  v.collision_pc = msg.collision_pc;
  v.collision_depth = msg.collision_depth;
  v.turn_in_contact = msg.turn_in_contact;
  v.ends_in_contact = msg.ends_in_contact;
  v.occupied_max = static_cast<int>(msg.occupied_max);
  v.min_near_ratio = msg.min_near_ratio;
  v.body_counts.assign(msg.body_counts.begin(), msg.body_counts.end());
  v.start_occupied = static_cast<int>(msg.start_occupied);
  v.see_through_points = static_cast<int>(msg.see_through_points);
  v.slam_lost = msg.slam_lost;
  v.floor_unknown = msg.floor_unknown;
  v.enters_failed = msg.enters_failed;
  v.prefix_frames = static_cast<int>(msg.prefix_frames);
  v.c_new = msg.c_new, v.c_front = msg.c_front, v.coverage = msg.coverage, v.progress = msg.progress;
  v.goal = msg.goal, v.opening = msg.opening;
  v.short_unclear = msg.short_unclear;
  v.turns_back = msg.turns_back;
  v.rewound_before = msg.rewound_before;
  v.score = msg.score;
  v.admissible = msg.admissible;
  v.yielded = msg.yielded;
  v.reason = msg.reason;
  return v;
}

valerant::GroundTruth toMsg(const FrameTruth& truth, bool with_depth) {
  valerant::GroundTruth msg;
  msg.camera_to_world = toMsg(truth.camera_to_world);
  if (with_depth) msg.depth = toCompressedImageMsg(truth.depth_m);
  msg.in_solid = truth.in_solid;
  msg.floor_z = truth.floor_z;
  msg.hull_in_solid = truth.hull_in_solid;
  msg.hull_in_clip_only = truth.hull_in_clip_only;
  msg.outside_world = truth.outside_world;
  return msg;
}

FrameTruth fromMsg(const valerant::GroundTruth& msg) {
  FrameTruth t;
  t.camera_to_world = fromMsg(msg.camera_to_world);
  t.depth_m = fromCompressedImageMsg(msg.depth);
  t.in_solid = msg.in_solid;
  t.floor_z = msg.floor_z;
  t.hull_in_solid = msg.hull_in_solid;
  t.hull_in_clip_only = msg.hull_in_clip_only;
  t.outside_world = msg.outside_world;
  return t;
}

TrackingState trackingStateFromName(const std::string& name) {
  for (TrackingState s : {TrackingState::kInitializing, TrackingState::kTracking, TrackingState::kLost})
    if (name == toString(s)) return s;
  throw InputError("tracking state '" + name + "'", "unknown");
}

valerant::SlamFrame toMsg(const TrackedFrame& frame, const KeyframeCloud* keyframe, bool with_depth) {
  valerant::SlamFrame msg;
  msg.header.frame_id = "map";
  msg.state = toString(frame.state);
  msg.camera_to_map = toMsg(frame.camera_to_map);
  msg.keyframe = keyframe != nullptr;
  msg.parallax_free = frame.rotation_only;
  if (with_depth) {
    msg.depth = toImageMsg(frame.depth);
    msg.confidence = toImageMsg(frame.confidence);
  }
  if (keyframe) {
    msg.keyframe_index = static_cast<uint32_t>(keyframe->keyframe);
    msg.keyframe_frame = static_cast<uint32_t>(keyframe->frame);
    msg.keyframe_pose = toMsg(keyframe->camera_to_map);
    msg.cloud = toCloudMsg(keyframe->points, "map");
  }
  return msg;
}

TrackedFrame trackedFrameFromMsg(const valerant::SlamFrame& msg) {
  TrackedFrame f;
  f.state = trackingStateFromName(msg.state);
  f.camera_to_map = fromMsg(msg.camera_to_map);
  f.keyframe = msg.keyframe;
  f.rotation_only = msg.parallax_free;
  f.depth = fromImageMsg(msg.depth);
  f.confidence = fromImageMsg(msg.confidence);
  if (f.confidence.size() != f.depth.size()) throw InputError("slam frame's confidence", "not the size of its depth");
  return f;
}

KeyframeCloud keyframeFromMsg(const valerant::SlamFrame& msg) {
  KeyframeCloud kf;
  kf.keyframe = static_cast<int>(msg.keyframe_index);
  kf.frame = static_cast<int>(msg.keyframe_frame);
  kf.camera_to_map = fromMsg(msg.keyframe_pose);
  kf.points = fromCloudMsg(msg.cloud);
  return kf;
}

valerant::StateDigest digest(size_t frames, size_t keyframes, const Eigen::Isometry3d& pose) {
  valerant::StateDigest d;
  d.frames = static_cast<uint32_t>(frames);
  d.keyframes = static_cast<uint32_t>(keyframes);
  d.pose = toMsg(pose);
  return d;
}

}  // namespace valerant::bridge
