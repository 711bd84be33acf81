#pragma once
// The main() of a node that is one object serving callbacks: init, construct it with
// the public and private node handles, spin. A node that cannot start (a missing
// parameter, an unreachable peer, a bad map) logs FATAL with its name and exits 1.
#include <exception>
#include <ros/ros.h>

namespace valerant::bridge {

template <class Node>
int spinNode(int argc, char** argv, const char* name) {
  ::ros::init(argc, argv, name);
  try {
    Node node(::ros::NodeHandle(), ::ros::NodeHandle("~"));
    ::ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM(name << ": " << e.what());
    return 1;
  }
  return 0;
}

}  // namespace valerant::bridge
