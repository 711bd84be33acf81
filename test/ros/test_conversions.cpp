// Every conversion of valerant/ros/conversions.h: core type -> message -> core type
// gives back the same value, bit for bit (images included), and bad messages are
// InputErrors naming what is wrong. Needs no ROS master.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <opencv2/imgcodecs.hpp>

#include "valerant/common/error.h"
#include "valerant/ros/conversions.h"

namespace valerant::bridge {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

Eigen::Isometry3d somePose() {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(1.0 / 3, -2.5e3, 7e-9);
  return pose;
}

// Every pixel differs from its neighbours so a swapped channel or row shows.
cv::Mat someRgb(int rows = 5, int cols = 7) {
  cv::Mat rgb(rows, cols, CV_8UC3);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) rgb.at<cv::Vec3b>(r, c) = cv::Vec3b(r * 40 + c, 255 - c * 30, (r * c * 17) % 256);
  return rgb;
}

// Depth with sky (NaN), an infinity, a denormal and values no 16-bit code keeps.
cv::Mat someDepth(int rows = 4, int cols = 6) {
  cv::Mat depth(rows, cols, CV_32FC1);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) depth.at<float>(r, c) = 0.1f + r * 3.7f + c / 3.0f;
  depth.at<float>(0, 0) = kNaN;
  depth.at<float>(1, 2) = std::numeric_limits<float>::infinity();
  depth.at<float>(2, 3) = std::numeric_limits<float>::denorm_min();
  return depth;
}

// Same type, size and bits (NaN equals NaN).
void expectSameImage(const cv::Mat& a, const cv::Mat& b) {
  ASSERT_EQ(a.type(), b.type());
  ASSERT_EQ(a.size(), b.size());
  for (int r = 0; r < a.rows; ++r)
    EXPECT_EQ(0, std::memcmp(a.ptr(r), b.ptr(r), a.cols * a.elemSize())) << "row " << r;
}

TEST(Conversions, IsometryRoundTripIsExact) {
  const Eigen::Isometry3d pose = somePose();
  EXPECT_EQ(fromMsg(toMsg(pose)).matrix(), pose.matrix());
}

TEST(Conversions, IsometryRejectsNaNAndNonRotations) {
  valerant::Isometry msg = toMsg(somePose());
  msg.m[3] = std::nan("");
  EXPECT_THROW(fromMsg(msg), InputError);
  msg = toMsg(Eigen::Isometry3d::Identity());
  msg.m[0] = 2;  // x axis stretched
  EXPECT_THROW(fromMsg(msg), InputError);
}

TEST(Conversions, PoseMsgHoldsTheQuaternionOfTheRotation) {
  // 90 degrees about z, at (1, 2, 3): q = (0, 0, sin 45, cos 45).
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(1, 2, 3);
  const geometry_msgs::Pose msg = toPoseMsg(pose);
  EXPECT_EQ(msg.position.x, 1);
  EXPECT_EQ(msg.position.y, 2);
  EXPECT_EQ(msg.position.z, 3);
  EXPECT_NEAR(msg.orientation.x, 0, 1e-15);
  EXPECT_NEAR(msg.orientation.y, 0, 1e-15);
  EXPECT_NEAR(msg.orientation.z, std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(msg.orientation.w, std::sqrt(0.5), 1e-15);
}

TEST(Conversions, RawImagesRoundTripExactly) {
  const cv::Mat rgb = someRgb(), depth = someDepth();
  const sensor_msgs::Image rgb_msg = toImageMsg(rgb), depth_msg = toImageMsg(depth);
  EXPECT_EQ(rgb_msg.encoding, "rgb8");
  EXPECT_EQ(depth_msg.encoding, "32FC1");
  expectSameImage(fromImageMsg(rgb_msg), rgb);
  expectSameImage(fromImageMsg(depth_msg), depth);
  // A view into a larger image (rows not contiguous) travels as its own pixels.
  const cv::Mat big = someRgb(9, 11);
  const cv::Mat view = big(cv::Rect(2, 3, 5, 4));
  expectSameImage(fromImageMsg(toImageMsg(view)), view);
  EXPECT_TRUE(fromImageMsg(toImageMsg(cv::Mat())).empty());
}

TEST(Conversions, RawImagesRejectUnknownEncodingsAndShortData) {
  EXPECT_THROW(toImageMsg(cv::Mat(2, 2, CV_16UC1)), InputError);
  sensor_msgs::Image msg = toImageMsg(someRgb());
  msg.encoding = "bgr8";
  EXPECT_THROW(fromImageMsg(msg), InputError);
  msg = toImageMsg(someRgb());
  msg.data.pop_back();
  EXPECT_THROW(fromImageMsg(msg), InputError);
}

TEST(Conversions, CompressedImagesRoundTripExactly) {
  const cv::Mat rgb = someRgb(), depth = someDepth();
  const sensor_msgs::CompressedImage rgb_msg = toCompressedImageMsg(rgb), depth_msg = toCompressedImageMsg(depth);
  EXPECT_EQ(rgb_msg.format, kRgbPngFormat);
  EXPECT_EQ(depth_msg.format, kDepthPngFormat);
  expectSameImage(fromCompressedImageMsg(rgb_msg), rgb);
  expectSameImage(fromCompressedImageMsg(depth_msg), depth);
  const cv::Mat big = someDepth(9, 11);
  const cv::Mat view = big(cv::Rect(1, 2, 6, 5));
  expectSameImage(fromCompressedImageMsg(toCompressedImageMsg(view)), view);
  const sensor_msgs::CompressedImage empty = toCompressedImageMsg(cv::Mat());
  EXPECT_TRUE(empty.data.empty());
  EXPECT_TRUE(fromCompressedImageMsg(empty).empty());
}

TEST(Conversions, CompressedColourIsAPngInViewerOrder) {
  // A standard decoder (OpenCV's gives BGR) sees the colours, not swapped channels.
  cv::Mat red(2, 3, CV_8UC3, cv::Scalar(255, 0, 0));  // rgb
  const sensor_msgs::CompressedImage msg = toCompressedImageMsg(red);
  const cv::Mat bgr = cv::imdecode(msg.data, cv::IMREAD_UNCHANGED);
  ASSERT_EQ(bgr.type(), CV_8UC3);
  EXPECT_EQ(bgr.at<cv::Vec3b>(1, 2), cv::Vec3b(0, 0, 255));
}

TEST(Conversions, CompressedImagesRejectOtherFormatsAndBadData) {
  EXPECT_THROW(toCompressedImageMsg(cv::Mat(2, 2, CV_16UC1)), InputError);
  sensor_msgs::CompressedImage msg = toCompressedImageMsg(someRgb());
  msg.format = "jpeg";
  EXPECT_THROW(fromCompressedImageMsg(msg), InputError);
  msg = toCompressedImageMsg(someRgb());
  msg.data.resize(msg.data.size() / 2);
  EXPECT_THROW(fromCompressedImageMsg(msg), InputError);
  // Colour bytes labelled as depth: a 3-channel PNG is no float image.
  msg = toCompressedImageMsg(someRgb());
  msg.format = kDepthPngFormat;
  EXPECT_THROW(fromCompressedImageMsg(msg), InputError);
}

TEST(Conversions, CloudsRoundTripExactly) {
  const std::vector<CloudPoint> points = {{{1.5f, -2.25f, 1e-7f}, {255, 0, 17}, 4.5f}, {{0, 0, 0}, {1, 2, 3}, 0}};
  const sensor_msgs::PointCloud2 msg = toCloudMsg(points, "map");
  EXPECT_EQ(msg.header.frame_id, "map");
  const std::vector<CloudPoint> back = fromCloudMsg(msg);
  ASSERT_EQ(back.size(), points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(back[i].position, points[i].position);
    EXPECT_EQ(back[i].rgb, points[i].rgb);
    EXPECT_EQ(back[i].confidence, points[i].confidence);
  }
  EXPECT_TRUE(fromCloudMsg(toCloudMsg({}, "map")).empty());
}

TEST(Conversions, FusedCloudsRoundTripExactly) {
  const std::vector<FusedPoint> points = {{{1.5f, -2.25f, 3}, {9, 8, 7}, 2.5f, -0.125f}};
  const std::vector<FusedPoint> back = fromFusedCloudMsg(toFusedCloudMsg(points, "map"));
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].position, points[0].position);
  EXPECT_EQ(back[0].rgb, points[0].rgb);
  EXPECT_EQ(back[0].confidence, points[0].confidence);
  EXPECT_EQ(back[0].h, points[0].h);
}

TEST(Conversions, CloudsRejectMissingFieldsAndShortData) {
  const std::vector<CloudPoint> points = {{{1, 2, 3}, {4, 5, 6}, 7}};
  // A plain cloud has no h: it is no fused cloud.
  EXPECT_THROW(fromFusedCloudMsg(toCloudMsg(points, "map")), InputError);
  sensor_msgs::PointCloud2 msg = toCloudMsg(points, "map");
  msg.data.pop_back();
  EXPECT_THROW(fromCloudMsg(msg), InputError);
}

TEST(Conversions, FloorRoundTripIsExact) {
  FloorPlane floor;
  floor.q = {0.1, 0.2, 0.3};
  floor.n = Eigen::Vector3d(1, -2, 2) / 3;
  floor.c = {4, 5, 6.5};
  floor.known = false;
  floor.reliable = true;
  floor.support = 123;
  const valerant::Floor msg = toMsg(floor, 9);
  EXPECT_EQ(msg.keyframe, 9u);
  const FloorPlane back = fromMsg(msg);
  EXPECT_EQ(back.q, floor.q);
  EXPECT_EQ(back.n, floor.n);
  EXPECT_EQ(back.c, floor.c);
  EXPECT_EQ(back.known, floor.known);
  EXPECT_EQ(back.reliable, floor.reliable);
  EXPECT_EQ(back.support, floor.support);
}

TEST(Conversions, VerdictRoundTripIsExact) {
  BranchVerdict v;
  v.candidate = "uw@31";
  v.rotation_only = true;
  v.collision_pc = true;
  v.collision_depth = false;
  v.turn_in_contact = true;
  v.ends_in_contact = true;
  v.occupied_max = 12;
  v.body_counts = {0, 3, 12, 7};
  v.start_occupied = 44;
  v.see_through_points = 17;
  v.min_near_ratio = 0.1;
  v.slam_lost = true;
  v.floor_unknown = true;
  v.enters_failed = true;
  v.prefix_frames = 31;
  v.c_new = 1.0 / 3, v.c_front = 2.5, v.coverage = 1.0 / 3 + 1.25, v.progress = -0.7;
  v.goal = -0.375, v.opening = 0.625;
  v.short_unclear = true;
  v.turns_back = true;
  v.rewound_before = true;
  v.score = 3.14159;
  v.admissible = false;
  v.yielded = true;
  v.reason = "collision_pc";
  const valerant::Verdict msg = toMsg(v, {{1, 2, 3}, {4, 5, 6}});
  ASSERT_EQ(msg.centres.size(), 2u);
  EXPECT_EQ(msg.centres[1].y, 5);
  const BranchVerdict back = fromMsg(msg);
  EXPECT_EQ(back.candidate, v.candidate);
  EXPECT_EQ(back.rotation_only, v.rotation_only);
  EXPECT_EQ(back.collision_pc, v.collision_pc);
  EXPECT_EQ(back.collision_depth, v.collision_depth);
  EXPECT_EQ(back.occupied_max, v.occupied_max);
  EXPECT_EQ(back.turn_in_contact, v.turn_in_contact);
  EXPECT_EQ(back.ends_in_contact, v.ends_in_contact);
  EXPECT_EQ(back.body_counts, v.body_counts);
  EXPECT_EQ(back.start_occupied, v.start_occupied);
  EXPECT_EQ(back.see_through_points, v.see_through_points);
  EXPECT_EQ(back.min_near_ratio, v.min_near_ratio);
  EXPECT_EQ(back.slam_lost, v.slam_lost);
  EXPECT_EQ(back.floor_unknown, v.floor_unknown);
  EXPECT_EQ(back.enters_failed, v.enters_failed);
  EXPECT_EQ(back.prefix_frames, v.prefix_frames);
  EXPECT_EQ(back.c_new, v.c_new);
  EXPECT_EQ(back.c_front, v.c_front);
  EXPECT_EQ(back.coverage, v.coverage);
  EXPECT_EQ(back.progress, v.progress);
  EXPECT_EQ(back.goal, v.goal);
  EXPECT_EQ(back.opening, v.opening);
  EXPECT_EQ(back.short_unclear, v.short_unclear);
  EXPECT_EQ(back.turns_back, v.turns_back);
  EXPECT_EQ(back.rewound_before, v.rewound_before);
  EXPECT_EQ(back.score, v.score);
  EXPECT_EQ(back.admissible, v.admissible);
  EXPECT_EQ(back.yielded, v.yielded);
  EXPECT_EQ(back.reason, v.reason);
}

TEST(Conversions, GroundTruthRoundTripIsExactWithAndWithoutDepth) {
  FrameTruth truth;
  truth.camera_to_world = somePose();
  truth.depth_m = someDepth();
  truth.in_solid = true;
  truth.floor_z = -24.125;
  truth.hull_in_solid = false;
  truth.hull_in_clip_only = true;
  truth.outside_world = true;
  const FrameTruth back = fromMsg(toMsg(truth, true));
  EXPECT_EQ(back.camera_to_world.matrix(), truth.camera_to_world.matrix());
  expectSameImage(back.depth_m, truth.depth_m);
  EXPECT_EQ(back.in_solid, truth.in_solid);
  EXPECT_EQ(back.floor_z, truth.floor_z);
  EXPECT_EQ(back.hull_in_solid, truth.hull_in_solid);
  EXPECT_EQ(back.hull_in_clip_only, truth.hull_in_clip_only);
  EXPECT_EQ(back.outside_world, truth.outside_world);
  EXPECT_TRUE(fromMsg(toMsg(truth, false)).depth_m.empty());
}

TEST(Conversions, TrackingStatesRoundTripByName) {
  for (TrackingState s : {TrackingState::kInitializing, TrackingState::kTracking, TrackingState::kLost})
    EXPECT_EQ(trackingStateFromName(toString(s)), s);
  EXPECT_THROW(trackingStateFromName("sleeping"), InputError);
}

TEST(Conversions, TrackedFrameAndKeyframeRoundTripExactly) {
  TrackedFrame frame;
  frame.state = TrackingState::kTracking;
  frame.camera_to_map = somePose();
  frame.keyframe = true;
  frame.rotation_only = true;
  frame.depth = someDepth();
  frame.confidence = cv::Mat(frame.depth.size(), CV_32FC1, cv::Scalar(1));
  KeyframeCloud keyframe;
  keyframe.keyframe = 4;
  keyframe.frame = 17;
  keyframe.camera_to_map = somePose().inverse();
  keyframe.points = {{{1, 2, 3}, {4, 5, 6}, 7.5f}};
  const valerant::SlamFrame msg = toMsg(frame, &keyframe, true);
  const TrackedFrame back = trackedFrameFromMsg(msg);
  EXPECT_EQ(back.state, frame.state);
  EXPECT_EQ(back.camera_to_map.matrix(), frame.camera_to_map.matrix());
  EXPECT_EQ(back.keyframe, frame.keyframe);
  EXPECT_EQ(back.rotation_only, frame.rotation_only);
  expectSameImage(back.depth, frame.depth);
  expectSameImage(back.confidence, frame.confidence);  // free-space evidence reads it (branch_check.h)
  const KeyframeCloud kf = keyframeFromMsg(msg);
  EXPECT_EQ(kf.keyframe, keyframe.keyframe);
  EXPECT_EQ(kf.frame, keyframe.frame);
  EXPECT_EQ(kf.camera_to_map.matrix(), keyframe.camera_to_map.matrix());
  ASSERT_EQ(kf.points.size(), 1u);
  EXPECT_EQ(kf.points[0].position, keyframe.points[0].position);
  EXPECT_EQ(kf.points[0].rgb, keyframe.points[0].rgb);
  EXPECT_EQ(kf.points[0].confidence, keyframe.points[0].confidence);
  // Without a keyframe and without depth: the flag is off and the depth stays home.
  const valerant::SlamFrame plain = toMsg(frame, nullptr, false);
  EXPECT_FALSE(plain.keyframe);
  EXPECT_TRUE(trackedFrameFromMsg(plain).depth.empty());
  EXPECT_TRUE(trackedFrameFromMsg(plain).confidence.empty());
  // A confidence that is not the depth's size is named, not read past its end.
  valerant::SlamFrame odd = msg;
  odd.confidence = toImageMsg(cv::Mat(2, 2, CV_32FC1, cv::Scalar(1)));
  EXPECT_THROW(trackedFrameFromMsg(odd), InputError);
}

TEST(Conversions, DigestHoldsCountsAndPose) {
  const valerant::StateDigest d = digest(42, 7, somePose());
  EXPECT_EQ(d.frames, 42u);
  EXPECT_EQ(d.keyframes, 7u);
  EXPECT_EQ(fromMsg(d.pose).matrix(), somePose().matrix());
}

}  // namespace
}  // namespace valerant::bridge
