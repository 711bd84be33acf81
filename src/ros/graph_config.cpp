#include "valerant/ros/graph_config.h"

#include <ros/param.h>

#include <iomanip>
#include <sstream>
#include <utility>

#include "valerant/common/error.h"

namespace valerant::bridge {
namespace {

// A parameter's value as the YAML text of an override.
std::string yamlText(const XmlRpc::XmlRpcValue& v, const std::string& name) {
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return static_cast<bool>(const_cast<XmlRpc::XmlRpcValue&>(v)) ? "true" : "false";
    case XmlRpc::XmlRpcValue::TypeInt:
      return std::to_string(static_cast<int>(const_cast<XmlRpc::XmlRpcValue&>(v)));
    case XmlRpc::XmlRpcValue::TypeDouble: {
      std::ostringstream text;
      text << std::setprecision(17) << static_cast<double>(const_cast<XmlRpc::XmlRpcValue&>(v));
      return text.str();
    }
    case XmlRpc::XmlRpcValue::TypeString:
      return static_cast<std::string>(const_cast<XmlRpc::XmlRpcValue&>(v));
    default:
      throw InputError("parameter " + name, "expected a number, a string or true/false");
  }
}

std::string configNamespace(const ::ros::NodeHandle& nh) {
  // A nodelet in the root namespace gets a handle whose namespace is "", from which
  // the master's parameter search finds nothing; "" means "/" here.
  const std::string from = nh.getNamespace().empty() ? "/" : nh.getNamespace();
  std::string ns;
  if (!::ros::param::search(from, "valerant_config", ns))
    throw InputError("parameter valerant_config", "not found above " + from + " (launch files set it)");
  return ns;
}

}  // namespace

ConfigDocument loadGraphConfigDocument(const ::ros::NodeHandle& nh) {
  const std::string ns = configNamespace(nh);
  std::string file;
  nh.getParam(ns + "/file", file);
  ConfigDocument doc = ConfigDocument::load(file.empty() ? defaultConfigPath() : file);
  // Launch arguments, each standing for one key of the file. Launch files default them
  // to "" (not given): the file's value stands.
  static const std::pair<const char*, const char*> kParameterKeys[] = {
      {"map", "world.map"},         {"spawn", "world.spawn"},
      {"seed", "world.seed"},       {"backend", "world.backend"},
      {"width", "world.width"},     {"height", "world.height"},
      {"slam", "slam.backend"},     {"budget", "policy.budget_steps"},
      {"policy", "policy.kind"},    {"rf", "floor.enabled"},
      {"col_pc", "collision.pointcloud_enabled"}, {"col_depth", "collision.depth_enabled"},
      {"dp", "dead_pocket.enabled"}};
  for (const auto& [parameter, key] : kParameterKeys) {
    const std::string name = ns + "/" + parameter;
    XmlRpc::XmlRpcValue value;
    if (!nh.getParam(name, value)) continue;
    const std::string text = yamlText(value, name);
    if (text.empty()) continue;
    doc.set(key, text, "parameter " + name + " (" + text + ")");
  }
  // `set`: any keys, as whitespace-separated key=value assignments (`--set` of the tools),
  // applied last.
  const std::string set_name = ns + "/set";
  XmlRpc::XmlRpcValue set_value;
  if (nh.getParam(set_name, set_value)) {
    if (set_value.getType() != XmlRpc::XmlRpcValue::TypeString)
      throw InputError("parameter " + set_name, "expected key=value assignments separated by spaces (a string)");
    std::istringstream in(static_cast<std::string>(set_value));
    for (std::string assignment; in >> assignment;)
      doc.setAssignment(assignment, "parameter " + set_name + " (" + assignment + ")");
  }
  return doc;
}

Config loadGraphConfig(const ::ros::NodeHandle& nh) { return loadGraphConfigDocument(nh).parse(); }

double requiredDouble(const ::ros::NodeHandle& private_nh, const std::string& name) {
  double v;
  if (!private_nh.getParam(name, v)) throw InputError("parameter " + private_nh.resolveName(name), "not set");
  return v;
}

int requiredInt(const ::ros::NodeHandle& private_nh, const std::string& name) {
  int v;
  if (!private_nh.getParam(name, v)) throw InputError("parameter " + private_nh.resolveName(name), "not set");
  return v;
}

std::string requiredString(const ::ros::NodeHandle& private_nh, const std::string& name) {
  std::string v;
  if (!private_nh.getParam(name, v)) throw InputError("parameter " + private_nh.resolveName(name), "not set");
  return v;
}

Config explorerConfig(const ConfigDocument& document) {
  Config config = document.parse();
  if (config.loop_closure.enabled && config.loop_closure.max_candidates > 0)
    throw InputError("loop_closure.max_candidates",
                     std::to_string(config.loop_closure.max_candidates) +
                         " with loop_closure.enabled is not supported in the ROS graph (the explorer receives no rollout "
                         "images to match); set it to 0 for the eye height alone, or run valerant_explore for loops");
  return config;
}

}  // namespace valerant::bridge
