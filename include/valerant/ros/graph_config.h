#pragma once
// The one configuration every node of a graph shares. Each node finds the parameter
// namespace `valerant_config` by searching up from its own namespace (so a graph can be
// launched under any namespace) and reads:
//   file                  config YAML (default: config/valerant.yaml of the source tree)
//   map spawn seed slam backend width height budget policy   overrides of the file
//   rf col_pc col_depth dp                                      ablation switches (bool)
//   set                   any overrides: "floor.enabled=false policy.budget_steps=3"
// A parameter that is absent or "" (the launch files' default) overrides nothing: the
// file's value stands. `set` is applied last.
// Every node reads the same values, so all of them build the same action sequences,
// floor estimators and collision tests as valerant_explore with the same flags. The
// parameters are overrides of the file's keys (config.h ConfigDocument), checked as
// strictly as the file: a bad value is an error naming the parameter.
#include <ros/node_handle.h>
#include <string>

#include "valerant/config/config.h"

namespace valerant::bridge {

// The file with the parameters applied; throws InputError for a bad file or value.
ConfigDocument loadGraphConfigDocument(const ::ros::NodeHandle& nh);
// loadGraphConfigDocument(nh).parse().
Config loadGraphConfig(const ::ros::NodeHandle& nh);
// What the graph's explorer runs: `document` parsed, refusing what the graph cannot
// carry. Loop closure matches candidates on rollout images, which stream to branch_slam
// and never reach the explorer, so loop_closure.enabled needs loop_closure.max_candidates
// 0 (no loops: the eye height alone, which reads only the keyframes' floors).
Config explorerConfig(const ConfigDocument& document);

// A private parameter that must be set (launch files give every one); InputError names it.
double requiredDouble(const ::ros::NodeHandle& private_nh, const std::string& name);
int requiredInt(const ::ros::NodeHandle& private_nh, const std::string& name);
std::string requiredString(const ::ros::NodeHandle& private_nh, const std::string& name);

}  // namespace valerant::bridge
