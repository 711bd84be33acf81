#pragma once
// Names of the graph's topics, services and actions, relative to the graph's root
// namespace, where every node lives.
//
//   world_model/{checkpoint,restore,drop,commit,reset,get_rollout}  services
//   world_model/rollout                                             action
//   world_model/camera_info, world_model/context                   latched topics
//   branch/<c>/frames -> branch_slam -> branch/<c>/tracked -> floor_estimator ->
//   branch/<c>/floor -> collision_checker -> branch/<c>/result -> explorer
//   branch/<c>/slam/{checkpoint,restore,drop,commit,track_context}  services
//   floor_estimator/{checkpoint,restore,drop,commit,floor_context,floor_at}
//   collision_checker/{checkpoint,restore,drop,commit,reset}
//   policy_arbiter/select_branch, explorer/explore (action)
//   decision, map_update (explorer -> map_fusion) and map/* (map_fusion)
#include <string>

namespace valerant::bridge {

inline std::string branchName(const std::string& candidate, const std::string& leaf) {
  return "branch/" + candidate + "/" + leaf;
}
inline const char* kWorldModel = "world_model";
inline const char* kFloorEstimator = "floor_estimator";
inline const char* kCollisionChecker = "collision_checker";
inline const char* kPolicyArbiter = "policy_arbiter";

}  // namespace valerant::bridge
