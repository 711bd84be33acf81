#include "valerant/ros/graph_config.h"

#include <ros/param.h>

#include "valerant/common/error.h"

namespace valerant::bridge {
namespace {

template <class T>
void override(const ::ros::NodeHandle& nh, const std::string& ns, const std::string& key, T& value) {
  T v;
  if (nh.getParam(ns + "/" + key, v)) value = v;
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

std::string graphConfigFile(const ::ros::NodeHandle& nh) {
  std::string file;
  nh.getParam(configNamespace(nh) + "/file", file);
  return file.empty() ? defaultConfigPath() : file;
}

Config loadGraphConfig(const ::ros::NodeHandle& nh) {
  const std::string ns = configNamespace(nh);
  Config c = loadConfig(graphConfigFile(nh));
  override(nh, ns, "map", c.world.map);
  override(nh, ns, "spawn", c.world.spawn);
  int seed = static_cast<int>(c.world.seed);
  override(nh, ns, "seed", seed);
  if (seed < 0) throw InputError("parameter " + ns + "/seed", "must be >= 0");
  c.world.seed = static_cast<uint32_t>(seed);
  override(nh, ns, "backend", c.world.backend);
  override(nh, ns, "width", c.world.width);
  override(nh, ns, "height", c.world.height);
  override(nh, ns, "slam", c.slam.backend);
  override(nh, ns, "budget", c.policy.budget_steps);
  override(nh, ns, "policy", c.policy.kind);
  override(nh, ns, "rf", c.floor.enabled);
  override(nh, ns, "col_pc", c.collision.pointcloud_enabled);
  override(nh, ns, "col_depth", c.collision.depth_enabled);
  override(nh, ns, "dp", c.dead_pocket.enabled);
  if (c.policy.budget_steps < 1) throw InputError("parameter " + ns + "/budget", "must be >= 1");
  if (c.world.width < 1 || c.world.height < 1) throw InputError("parameter " + ns + "/width, height", "must be >= 1");
  return c;
}

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

}  // namespace valerant::bridge
