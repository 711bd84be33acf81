#pragma once
// Calls to the protocol's services. Every failure becomes an InputError that names the
// service: an unreachable node, or the node's own error (response.ok false).
#include <functional>
#include <ros/node_handle.h>
#include <ros/service_client.h>
#include <string>
#include <utility>

#include "valerant/common/error.h"

namespace valerant::bridge {

template <class Service>
void callChecked(::ros::ServiceClient& client, Service& srv) {
  if (!client.call(srv)) throw InputError("service " + client.getService(), "call failed (is its node running?)");
  if (!srv.response.ok) throw InputError("service " + client.getService(), srv.response.error);
}

// A persistent connection to one service, made anew when roscpp dropped it (its server
// restarted). A fresh connection per call means a master lookup and a TCP handshake
// every call, several at once every step: slower, and seen to fail now and then
// (ServiceClient::call false with the server alive). One link serves one caller at a
// time; roscpp's persistent clients are not for concurrent calls.
class ServiceLink {
 public:
  template <class Service>
  static ServiceLink to(::ros::NodeHandle nh, const std::string& name) {
    return ServiceLink(name, [nh, name]() mutable { return nh.serviceClient<Service>(name, true); });
  }

  template <class Service>
  void call(Service& srv) {
    if (!client_.isValid()) client_ = connect_();
    callChecked(client_, srv);
  }
  bool waitForExistence(::ros::Duration timeout) { return client_.waitForExistence(timeout); }
  const std::string& name() const { return name_; }

 private:
  ServiceLink(std::string name, std::function<::ros::ServiceClient()> connect)
      : name_(std::move(name)), connect_(std::move(connect)), client_(connect_()) {}

  std::string name_;
  std::function<::ros::ServiceClient()> connect_;
  ::ros::ServiceClient client_;
};

}  // namespace valerant::bridge
