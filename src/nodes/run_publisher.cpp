// run_publisher: a finished run directory (valerant_explore or the explorer node) back
// on the graph, so map_fusion and rviz show a saved map without exploring again.
//   param ~run_dir   the run directory (map/run_map.h: keyframes.pcd, keyframes.txt,
//                    config.yaml, report.json, trajectory from trajectory.txt)
//   pub   map_update (valerant/MapUpdate, latched): the explorer's own message, so the
//                    map_fusion node renders the saved map exactly as it rendered it live
//   pub   camera/image (sensor_msgs/Image, latched): the run's view.png, the
//                    player's last committed view, where the world model server puts
//                    the live one (a run without view.png publishes none)
//   tf    level -> map (static): the run's floor frame, origin at the start camera's
//                    foot, z up the anchor floor normal, x along the start heading; rviz
//                    views any SLAM frame (the visual SLAM's is arbitrary) from above in it
// A missing or truncated run directory is a fatal error that names the file.
#include <iostream>
#include <geometry_msgs/TransformStamped.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <valerant/MapUpdate.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "valerant/common/error.h"
#include "valerant/map/run_map.h"
#include "valerant/ros/conversions.h"
#include "valerant/ros/graph_config.h"

using namespace valerant;

namespace {

valerant::MapUpdate mapUpdateOf(const RunMap& run) {
  valerant::MapUpdate m;
  m.header.stamp = ::ros::Time::now();
  m.header.frame_id = "map";
  for (const auto& kf : run.map.keyframes()) {
    m.keyframe_ids.push_back(kf->id);
      m.keyframes.push_back(valerant::bridge::toFusedCloudMsg(kf->points, "map"));
    m.keyframe_poses.push_back(valerant::bridge::toMsg(kf->camera_to_map));
  }
  for (const auto& p : run.trajectory) m.trajectory.push_back(valerant::bridge::toMsg(p));
  m.grid_anchor = valerant::bridge::toMsg(run.frame.anchorFloor(), 0);
  m.grid_heading.x = run.frame.forward.x();
  m.grid_heading.y = run.frame.forward.y();
  m.grid_heading.z = run.frame.forward.z();
  return m;
}

geometry_msgs::TransformStamped levelToMap(const MapFrame& frame) {
  Eigen::Matrix3d level_from_map;
  const Eigen::Vector3d x = frame.forward.normalized(), z = frame.up.normalized();
  level_from_map.row(0) = x;
  level_from_map.row(1) = z.cross(x);
  level_from_map.row(2) = z;
  Eigen::Isometry3d map_in_level = Eigen::Isometry3d::Identity();
  map_in_level.linear() = level_from_map;
  map_in_level.translation() = -(level_from_map * frame.foot);
  geometry_msgs::TransformStamped t;
  t.header.stamp = ::ros::Time::now();
  t.header.frame_id = "level";
  t.child_frame_id = "map";
  const geometry_msgs::Pose pose = valerant::bridge::toPoseMsg(map_in_level);
  t.transform.translation.x = pose.position.x;
  t.transform.translation.y = pose.position.y;
  t.transform.translation.z = pose.position.z;
  t.transform.rotation = pose.orientation;
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  ::ros::init(argc, argv, "run_publisher");
  try {
    ::ros::NodeHandle nh, pnh("~");
    const std::string run_dir = valerant::bridge::requiredString(pnh, "run_dir");
    const RunMap run = loadRunMap(run_dir);
    ::ros::Publisher updates = nh.advertise<valerant::MapUpdate>("map_update", 1, true);
    updates.publish(mapUpdateOf(run));
    ::ros::Publisher view = nh.advertise<sensor_msgs::Image>("camera/image", 1, true);
    const std::string view_path = run_dir + "/view.png";
    if (std::filesystem::exists(view_path)) {
      cv::Mat rgb = cv::imread(view_path, cv::IMREAD_COLOR);
      if (rgb.empty()) throw InputError(view_path, "unreadable image");
      cv::cvtColor(rgb, rgb, cv::COLOR_BGR2RGB);
      sensor_msgs::Image image = valerant::bridge::toImageMsg(rgb);
      image.header.stamp = ::ros::Time::now();
      image.header.frame_id = "camera";
      view.publish(image);
    }
    tf2_ros::StaticTransformBroadcaster level;
    level.sendTransform(levelToMap(run.frame));
    ROS_INFO_STREAM("run_publisher: " << run_dir << ": " << run.map.keyframes().size() << " keyframes, "
                                      << run.trajectory.size() << " poses");
    ::ros::spin();
  } catch (const std::exception& e) {
    std::cerr << "run_publisher: error: " << e.what() << std::endl;  // see ros/node_main.h
    return 1;
  }
  return 0;
}
