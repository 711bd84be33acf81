#pragma once
// The main() of a node that is one object serving callbacks: init, construct it with
// the public and private node handles, spin. A node that cannot start (a missing
// parameter, an unreachable peer, a bad map) prints the error with its name and exits 1.
#include <ros/ros.h>

#include <exception>
#include <iostream>

namespace valerant::bridge {

template <class Node>
int spinNode(int argc, char** argv, const char* name) {
  ::ros::init(argc, argv, name);
  try {
    Node node(::ros::NodeHandle(), ::ros::NodeHandle("~"));
    ::ros::spin();
  } catch (const std::exception& e) {
    // std::cerr, not ROS_FATAL: rosconsole loses a message logged just before the process
    // returns (a mistyped launch argument died with exit code 1 and no word why).
    std::cerr << name << ": error: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}

}  // namespace valerant::bridge
