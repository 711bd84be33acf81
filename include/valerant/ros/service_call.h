#pragma once
// Calls a protocol service and turns every failure into an InputError that names the
// service: an unreachable node, or the node's own error (response.ok false).
#include <ros/service_client.h>

#include "valerant/common/error.h"

namespace valerant::bridge {

template <class Service>
void callChecked(::ros::ServiceClient& client, Service& srv) {
  if (!client.call(srv)) throw InputError("service " + client.getService(), "call failed (is its node running?)");
  if (!srv.response.ok) throw InputError("service " + client.getService(), srv.response.error);
}

}  // namespace valerant::bridge
