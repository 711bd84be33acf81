#include "valerant/ros/topic_links.h"

#include <ros/ros.h>

#include "valerant/common/error.h"

namespace valerant::bridge {

void connectInputs(std::vector<::ros::Subscriber>& inputs, const Resubscribe& resubscribe, double timeout_s,
                   const std::string& who) {
  const ::ros::WallTime deadline = ::ros::WallTime::now() + ::ros::WallDuration(timeout_s);
  ::ros::WallTime retry = ::ros::WallTime::now() + ::ros::WallDuration(kLinkRetryS);
  auto unconnected = [&] {
    std::string topics;
    for (const auto& s : inputs)
      if (s.getNumPublishers() == 0) topics += (topics.empty() ? "" : ", ") + s.getTopic();
    return topics;
  };
  std::string missing = unconnected();
  while (!missing.empty() && ::ros::ok() && ::ros::WallTime::now() < deadline) {
    ::ros::WallDuration(0.01).sleep();
    if (::ros::WallTime::now() >= retry) {
      for (size_t i = 0; i < inputs.size(); ++i)
        if (inputs[i].getNumPublishers() == 0) {
          ROS_WARN_STREAM(who << ": " << inputs[i].getTopic() << " still unconnected, subscribing again");
          inputs[i] = resubscribe(i);
        }
      retry = ::ros::WallTime::now() + ::ros::WallDuration(kLinkRetryS);
    }
    missing = unconnected();
  }
  if (!missing.empty())
    throw InputError(who, "no publisher connected to " + missing + " within " + std::to_string(timeout_s) +
                              " s (is every node of the graph running?)");
}

}  // namespace valerant::bridge
