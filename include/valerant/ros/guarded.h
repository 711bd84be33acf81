#pragma once
// Every service of the graph answers bad input with ok = false and the error text, logs
// it, and goes on serving: no exception ever leaves a callback and kills a node.
#include <exception>
#include <ros/console.h>
#include <string>

namespace valerant::bridge {

template <class Response, class Body>
bool guarded(const std::string& service, Response& response, Body&& body) {
  try {
    body();
    response.ok = true;
  } catch (const std::exception& e) {
    response.ok = false;
    response.error = e.what();
    ROS_ERROR_STREAM(service << ": " << e.what());
  }
  return true;  // the call itself succeeded; response.ok carries the outcome
}

}  // namespace valerant::bridge
