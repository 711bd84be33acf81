#pragma once
// A node object (constructed from the public and private node handles, like the ones
// spinNode() runs) as a nodelet. branch_slam, floor_estimator and collision_checker
// run as nodelets in one manager, so the per-frame messages between them (raw depth
// images and keyframe clouds) pass as shared pointers instead of being serialised
// and copied over TCP twice per frame. A nodelet that cannot start (a missing
// parameter, an unreachable peer) logs FATAL with its name and fails its load.
#include <exception>
#include <memory>
#include <nodelet/nodelet.h>

namespace valerant::bridge {

template <class Node>
class NodeletOf : public nodelet::Nodelet {
 private:
  void onInit() override {
    try {
      node_ = std::make_unique<Node>(getNodeHandle(), getPrivateNodeHandle());
    } catch (const std::exception& e) {
      NODELET_FATAL_STREAM(getName() << ": " << e.what());
      throw;
    }
  }

  std::unique_ptr<Node> node_;
};

}  // namespace valerant::bridge
