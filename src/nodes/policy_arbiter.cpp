// policy_arbiter: paper eq. 2 (or a baseline, policy.kind) over one step's judged
// candidates, as the service ~select_branch; it runs selectBranch() with the graph's
// policy config, exactly what the in-process loop calls.
#include <iostream>
#include <ros/ros.h>
#include <valerant/SelectBranch.h>

#include "valerant/common/error.h"
#include "valerant/explore/policy.h"
#include "valerant/ros/conversions.h"
#include "valerant/ros/graph_config.h"
#include "valerant/ros/guarded.h"

using namespace valerant;

int main(int argc, char** argv) {
  ::ros::init(argc, argv, "policy_arbiter");
  try {
    ::ros::NodeHandle nh, pnh("~");
    const Config config = valerant::bridge::loadGraphConfig(nh);
    auto select = [&](valerant::SelectBranch::Request& req, valerant::SelectBranch::Response& res) {
      return valerant::bridge::guarded("policy_arbiter/select_branch", res, [&] {
        std::vector<BranchVerdict> verdicts;
        for (const auto& v : req.verdicts) {
          if (v.candidate.empty()) throw InputError("verdict", "names no candidate");
          verdicts.push_back(valerant::bridge::fromMsg(v));
        }
        res.chosen = selectBranch(verdicts, config.policy, req.step_seed);
        for (size_t i = 0; i < verdicts.size(); ++i) {
          res.verdicts.push_back(valerant::bridge::toMsg(verdicts[i]));
          res.verdicts.back().centres = req.verdicts[i].centres;
        }
      });
    };
    const auto server = pnh.advertiseService<valerant::SelectBranch::Request, valerant::SelectBranch::Response>(
        "select_branch", select);
    ROS_INFO_STREAM("policy_arbiter: policy " << config.policy.kind);
    ::ros::spin();
  } catch (const std::exception& e) {
    std::cerr << "policy_arbiter: error: " << e.what() << std::endl;  // see ros/node_main.h
    return 1;
  }
  return 0;
}
