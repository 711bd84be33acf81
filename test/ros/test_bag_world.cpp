// The bag world backend reads what record.launch writes: PNG-compressed frames come
// back as the exact images that were recorded, and a bag of the older raw-image Frame
// format is refused with an error naming the bag. Needs no ROS master.
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <sensor_msgs/CameraInfo.h>
#include <topic_tools/shape_shifter.h>
#include <valerant/Context.h>
#include <valerant/Frame.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>

#include "valerant/common/error.h"
#include "valerant/ros/bag_world.h"
#include "valerant/ros/conversions.h"

namespace valerant::bridge {
namespace {

// A unique bag path under the test's temporary directory, removed afterwards.
class TempBag {
 public:
  TempBag() : path_(std::string(testing::TempDir()) + "valerant_bag_world_" +
                    testing::UnitTest::GetInstance()->current_test_info()->name() + ".bag") {}
  ~TempBag() { std::remove(path_.c_str()); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

cv::Mat gradient(int seed) {
  cv::Mat rgb(6, 8, CV_8UC3);
  for (int r = 0; r < rgb.rows; ++r)
    for (int c = 0; c < rgb.cols; ++c) rgb.at<cv::Vec3b>(r, c) = cv::Vec3b(seed + r, 2 * c, (seed * r + c) % 256);
  return rgb;
}

valerant::Frame frameMsg(const cv::Mat& rgb, uint64_t checkpoint, const std::string& candidate, uint32_t index,
                         uint32_t count) {
  valerant::Frame f;
  f.key.checkpoint_id = checkpoint;
  f.key.candidate = candidate;
  f.key.index = index;
  f.key.count = count;
  f.rgb = toCompressedImageMsg(rgb);
  FrameTruth truth;
  truth.camera_to_world = Eigen::Isometry3d::Identity();
  truth.depth_m = cv::Mat(rgb.size(), CV_32FC1, cv::Scalar(2.5f));
  truth.depth_m.at<float>(0, 0) = std::numeric_limits<float>::quiet_NaN();
  f.truth.push_back(toMsg(truth, true));
  return f;
}

void writeCameraInfo(rosbag::Bag& bag) {
  sensor_msgs::CameraInfo info;
  info.width = 8;
  info.height = 6;
  info.K = {10, 0, 4, 0, 10, 3, 0, 0, 1};
  bag.write("world_model/camera_info", ::ros::Time(1), info);
}

TEST(BagWorld, ReplaysTheRecordedImagesExactly) {
  TempBag file;
  const cv::Mat context_image = gradient(1), first = gradient(50), second = gradient(90);
  {
    rosbag::Bag bag(file.path(), rosbag::bagmode::Write);
    bag.setCompression(rosbag::compression::LZ4);  // as record.launch records
    writeCameraInfo(bag);
    valerant::Context context;
    context.frames.push_back(frameMsg(context_image, 0, "context", 0, 1));
    bag.write("world_model/context", ::ros::Time(1), context);
    bag.write("branch/uw/frames", ::ros::Time(2), frameMsg(first, 1, "uw", 0, 2));
    bag.write("branch/uw/frames", ::ros::Time(3), frameMsg(second, 1, "uw", 1, 2));
  }
  BagWorld world(file.path(), "/");
  EXPECT_EQ(world.intrinsics().width, 8);
  const Rollout context = world.context();
  ASSERT_EQ(context.frames.size(), 1u);
  EXPECT_EQ(cv::norm(context.frames[0], context_image, cv::NORM_INF), 0);
  EXPECT_EQ(world.checkpoint(), 1u);
  ActionSequence uw;
  uw.name = "uw";
  const Rollout r = world.rollout(uw);
  ASSERT_EQ(r.frames.size(), 2u);
  EXPECT_EQ(cv::norm(r.frames[0], first, cv::NORM_INF), 0);
  EXPECT_EQ(cv::norm(r.frames[1], second, cv::NORM_INF), 0);
  ASSERT_EQ(r.truth.size(), 2u);
  EXPECT_TRUE(std::isnan(r.truth[0].depth_m.at<float>(0, 0)));
  EXPECT_EQ(r.truth[0].depth_m.at<float>(5, 7), 2.5f);
}

// The valerant/Frame definition before the images were compressed (its md5 as rosbag
// stored it), written as raw bytes the way an old recording holds them.
TEST(BagWorld, RefusesABagOfTheOlderFrameFormatNamingIt) {
  TempBag file;
  {
    rosbag::Bag bag(file.path(), rosbag::bagmode::Write);
    writeCameraInfo(bag);
    topic_tools::ShapeShifter old_frame;
    old_frame.morph("0123456789abcdef0123456789abcdef", "valerant/Frame",
                    "std_msgs/Header header\nvalerant/FrameKey key\nsensor_msgs/Image rgb\nvalerant/GroundTruth[] truth\n",
                    "");
    std::vector<uint8_t> bytes(64, 0);
    ::ros::serialization::IStream stream(bytes.data(), static_cast<uint32_t>(bytes.size()));
    old_frame.read(stream);
    bag.write("branch/uw/frames", ::ros::Time(2), old_frame);
  }
  try {
    BagWorld world(file.path(), "/");
    FAIL() << "an old-format bag was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(file.path()), std::string::npos) << what;
    EXPECT_NE(what.find("older message format"), std::string::npos) << what;
    EXPECT_NE(what.find("record it again"), std::string::npos) << what;
  }
}

TEST(BagWorld, RefusesAMissingBagNamingIt) {
  try {
    BagWorld world("/nonexistent/episode.bag", "/");
    FAIL() << "a missing bag was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/episode.bag"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace valerant::bridge
