#include "valerant/ros/arbiter_client.h"

#include <valerant/SelectBranch.h>

#include "valerant/ros/conversions.h"
#include "valerant/ros/graph_names.h"
#include "valerant/ros/service_call.h"

namespace valerant::bridge {

ArbiterClient::ArbiterClient(::ros::NodeHandle nh, double connect_timeout_s)
    : client_(ServiceLink::to<valerant::SelectBranch>(nh, std::string(kPolicyArbiter) + "/select_branch")) {
  if (!client_.waitForExistence(::ros::Duration(connect_timeout_s)))
    throw InputError("service " + client_.name(), "not reachable (is policy_arbiter running?)");
}

int ArbiterClient::select(std::vector<BranchVerdict>& verdicts, uint64_t step_seed) {
  valerant::SelectBranch srv;
  for (const auto& v : verdicts) srv.request.verdicts.push_back(toMsg(v));
  srv.request.step_seed = step_seed;
  client_.call(srv);
  if (srv.response.verdicts.size() != verdicts.size())
    throw InputError("service " + client_.name(), "answered with a wrong number of verdicts");
  for (size_t i = 0; i < verdicts.size(); ++i) verdicts[i] = fromMsg(srv.response.verdicts[i]);
  return srv.response.chosen;
}

}  // namespace valerant::bridge
