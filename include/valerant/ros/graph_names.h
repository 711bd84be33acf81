#pragma once
// Names of the graph's topics, services and actions, relative to the graph's root
// namespace (every node but branch_slam lives there; branch_slam lives in
// branch/<candidate> and reaches the root through graphRoot()).
//
//   world_model/{checkpoint,restore,drop,commit,reset,get_rollout}  services
//   world_model/rollout                                             action
//   world_model/camera_info, world_model/context                   latched topics
//   branch/<c>/frames -> branch_slam -> branch/<c>/tracked -> floor_estimator ->
//   branch/<c>/floor -> collision_checker -> branch/<c>/result -> explorer
//   branch/<c>/slam/{checkpoint,restore,drop,commit,track_context}  services
//   floor_estimator/{checkpoint,restore,drop,commit,floor_context,floor_at}
//   policy_arbiter/select_branch, explorer/explore (action)
//   decision, map_update (explorer -> map_fusion) and map/* (map_fusion)
#include <ros/node_handle.h>
#include <string>

namespace valerant::bridge {

inline std::string branchName(const std::string& candidate, const std::string& leaf) {
  return "branch/" + candidate + "/" + leaf;
}
inline const char* kWorldModel = "world_model";
inline const char* kFloorEstimator = "floor_estimator";
inline const char* kPolicyArbiter = "policy_arbiter";

// The graph's root namespace seen from a node in branch/<candidate> ("/" or "/ns/").
std::string graphRoot(const ::ros::NodeHandle& branch_nh);

}  // namespace valerant::bridge
