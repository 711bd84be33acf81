#pragma once
// Exact conversions between the core's types and the protocol's messages. Poses travel
// as 3x4 float64 matrices, clouds and depth as float32, images as raw bytes or lossless
// PNG: a value that crosses the graph is bit-identical on the other side, which is what
// lets the node graph decide exactly as the in-process loop does (and a replayed bag
// exactly as its recording).
#include <Eigen/Geometry>
#include <geometry_msgs/Pose.h>
#include <opencv2/core.hpp>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <string>
#include <vector>

#include <valerant/Verdict.h>
#include <valerant/Floor.h>
#include <valerant/GroundTruth.h>
#include <valerant/Isometry.h>
#include <valerant/StateDigest.h>
#include <valerant/SlamFrame.h>

#include "valerant/explore/branch_verdict.h"
#include "valerant/geometry/floor_plane.h"
#include "valerant/map/map_fusion.h"
#include "valerant/slam/slam.h"
#include "valerant/world/world_model.h"

namespace valerant::bridge {

valerant::Isometry toMsg(const Eigen::Isometry3d& pose);
// Throws InputError when the matrix holds a NaN or infinity or is no rotation.
Eigen::Isometry3d fromMsg(const valerant::Isometry& msg);
geometry_msgs::Pose toPoseMsg(const Eigen::Isometry3d& pose);

// CV_8UC3 -> rgb8, CV_32F -> 32FC1 (an empty Mat gives an empty image).
sensor_msgs::Image toImageMsg(const cv::Mat& image);
// Throws InputError for an encoding other than rgb8 / 32FC1 or a size mismatch.
cv::Mat fromImageMsg(const sensor_msgs::Image& msg);

// The world model's frames (colour and truth depth), as streamed and recorded, losslessly
// compressed: CV_8UC3 rgb -> PNG (format kRgbPngFormat), CV_32FC1 -> its float32 bytes
// as a 4-channel 8-bit PNG (kDepthPngFormat; NaN survives). An empty Mat gives an
// empty message and back.
extern const char* const kRgbPngFormat;
extern const char* const kDepthPngFormat;
sensor_msgs::CompressedImage toCompressedImageMsg(const cv::Mat& image);
// Throws InputError naming the format for another format, or data that does not decode.
cv::Mat fromCompressedImageMsg(const sensor_msgs::CompressedImage& msg);

// x y z rgb confidence (float32, rgb packed as in PCL).
sensor_msgs::PointCloud2 toCloudMsg(const std::vector<CloudPoint>& points, const std::string& frame_id);
std::vector<CloudPoint> fromCloudMsg(const sensor_msgs::PointCloud2& msg);
// x y z rgb confidence h.
sensor_msgs::PointCloud2 toFusedCloudMsg(const std::vector<FusedPoint>& points, const std::string& frame_id);
std::vector<FusedPoint> fromFusedCloudMsg(const sensor_msgs::PointCloud2& msg);

valerant::Floor toMsg(const FloorPlane& floor, uint32_t frame);
FloorPlane fromMsg(const valerant::Floor& msg);

valerant::Verdict toMsg(const BranchVerdict& v, const std::vector<Eigen::Vector3d>& centres = {});
BranchVerdict fromMsg(const valerant::Verdict& msg);

// `with_depth` false leaves the depth image out (evaluation needs the rest only).
valerant::GroundTruth toMsg(const FrameTruth& truth, bool with_depth);
FrameTruth fromMsg(const valerant::GroundTruth& msg);

TrackingState trackingStateFromName(const std::string& name);
// A tracked frame (state, pose, keyframe and parallax flags, and its raw depth when
// `with_depth`; the confidence image stays home) and, when it made one, its keyframe
// cloud. The caller fills header and key.
valerant::SlamFrame toMsg(const TrackedFrame& frame, const KeyframeCloud* keyframe, bool with_depth);
// The tracked frame a SlamFrame message carries (state, pose, flags, depth).
TrackedFrame trackedFrameFromMsg(const valerant::SlamFrame& msg);
// Its keyframe cloud; only meaningful when msg.keyframe is set.
KeyframeCloud keyframeFromMsg(const valerant::SlamFrame& msg);

valerant::StateDigest digest(size_t frames, size_t keyframes, const Eigen::Isometry3d& pose);

}  // namespace valerant::bridge
