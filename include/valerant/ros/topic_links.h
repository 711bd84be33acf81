#pragma once
// Messages published before a subscriber's connection to the publisher is up are
// dropped without a trace. Every node that starts a chain of per-frame topics waits
// for its input links first, so the first rollout of an episode cannot vanish (a
// bag replay serves rollouts at once and lost the explorer's results that way).
// roscpp tries a subscriber's connection once, when it registers; if the publisher's
// node does not answer then (a loaded 2-core machine: the explorer once waited 120 s
// for a camera_info the world model had published 2 s after its start), it never
// tries again. So a link still down after kLinkRetryS is subscribed anew.
#include <ros/ros.h>
#include <ros/subscriber.h>
#include <ros/topic.h>
#include <functional>
#include <string>
#include <vector>

namespace valerant::bridge {

// How long a node waits for the links of the graph it was started with.
constexpr double kTopicLinkTimeoutS = 30.0;

// How long a subscription may stay unconnected (or a latched topic silent) before it
// is made anew.
constexpr double kLinkRetryS = 5.0;

// Makes subscriber `index` of a node's inputs again.
using Resubscribe = std::function<::ros::Subscriber(size_t index)>;

// Waits until every subscriber in `inputs` is connected to at least one publisher,
// replacing one still unconnected after kLinkRetryS by `resubscribe(i)`. Throws
// InputError naming `who` and the topics still without one after `timeout_s`.
void connectInputs(std::vector<::ros::Subscriber>& inputs, const Resubscribe& resubscribe, double timeout_s,
                   const std::string& who);

// The latched message on `topic`, subscribing anew every kLinkRetryS seconds, or
// nullptr after `timeout_s`.
template <class Message>
boost::shared_ptr<const Message> waitForLatched(const std::string& topic, ::ros::NodeHandle& nh, double timeout_s) {
  const ::ros::WallTime deadline = ::ros::WallTime::now() + ::ros::WallDuration(timeout_s);
  while (::ros::ok()) {
    const double left = (deadline - ::ros::WallTime::now()).toSec();
    if (left <= 0) break;
    if (auto m = ::ros::topic::waitForMessage<Message>(topic, nh, ::ros::Duration(std::min(left, kLinkRetryS))))
      return m;
  }
  return nullptr;
}

}  // namespace valerant::bridge
