#include "valerant/ros/graph_names.h"

#include "valerant/common/error.h"

namespace valerant::bridge {

std::string graphRoot(const ::ros::NodeHandle& branch_nh) {
  const std::string ns = branch_nh.getNamespace();  // e.g. /valerant/branch/uw
  const size_t at = ns.rfind("/branch/");
  if (at == std::string::npos) throw InputError("namespace " + ns, "is not branch/<candidate> of a graph");
  return ns.substr(0, at) + "/";
}

}  // namespace valerant::bridge
