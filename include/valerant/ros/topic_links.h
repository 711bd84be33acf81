#pragma once
// Messages published before a subscriber's connection to the publisher is up are
// dropped without a trace. Every node that starts a chain of per-frame topics waits
// for its input links first, so the first rollout of an episode cannot vanish (a
// bag replay serves rollouts at once and lost the explorer's results that way).
#include <ros/subscriber.h>
#include <string>
#include <vector>

namespace valerant::bridge {

// How long a node waits for the links of the graph it was started with.
constexpr double kTopicLinkTimeoutS = 30.0;

// Waits until every subscriber in `inputs` is connected to at least one publisher.
// Throws InputError naming `who` and the topics still without one after `timeout_s`.
void waitForPublishers(const std::vector<::ros::Subscriber>& inputs, double timeout_s, const std::string& who);

}  // namespace valerant::bridge
