#include "valerant/ros/world_model_client.h"

#include <ros/topic.h>
#include <sensor_msgs/CameraInfo.h>
#include <valerant/Checkpoint.h>
#include <valerant/Commit.h>
#include <valerant/Drop.h>
#include <valerant/GetRollout.h>
#include <valerant/Reset.h>
#include <valerant/Restore.h>

#include "valerant/ros/conversions.h"
#include "valerant/ros/graph_names.h"
#include "valerant/ros/topic_links.h"
#include "valerant/ros/service_call.h"

namespace valerant::bridge {
namespace {

std::string name(const std::string& leaf) { return std::string(kWorldModel) + "/" + leaf; }

}  // namespace

WorldModelClient::WorldModelClient(::ros::NodeHandle nh, double connect_timeout_s, double rollout_timeout_s)
    : nh_(nh),
      rollout_timeout_s_(rollout_timeout_s),
      checkpoint_(ServiceLink::to<valerant::Checkpoint>(nh, name("checkpoint"))),
      restore_(ServiceLink::to<valerant::Restore>(nh, name("restore"))),
      drop_(ServiceLink::to<valerant::Drop>(nh, name("drop"))),
      commit_(ServiceLink::to<valerant::Commit>(nh, name("commit"))),
      reset_(ServiceLink::to<valerant::Reset>(nh, name("reset"))),
      get_rollout_(ServiceLink::to<valerant::GetRollout>(nh, name("get_rollout"))),
      rollout_(nh, name("rollout"), true) {
  const ::ros::Duration timeout(connect_timeout_s);
  if (!rollout_.waitForServer(timeout) || !checkpoint_.waitForExistence(timeout))
    throw InputError("world model server " + nh.resolveName(kWorldModel), "not reachable");
  const auto info = waitForLatched<sensor_msgs::CameraInfo>(name("camera_info"), nh, connect_timeout_s);
  if (!info) throw InputError("topic " + nh.resolveName(name("camera_info")), "nothing received");
  intrinsics_.width = static_cast<int>(info->width);
  intrinsics_.height = static_cast<int>(info->height);
  intrinsics_.fx = info->K[0], intrinsics_.cx = info->K[2], intrinsics_.fy = info->K[4], intrinsics_.cy = info->K[5];
}

Rollout WorldModelClient::context() const {
  valerant::GetRollout srv;
  srv.request.rollout_id = 0;
  srv.request.with_images = true;  // called once at the start and once at the end of an episode
  get_rollout_.call(srv);
  Rollout r;
  r.candidate = "context";
  for (const auto& f : srv.response.frames) {
    if (!f.rgb.data.empty()) r.frames.push_back(valerant::bridge::fromCompressedImageMsg(f.rgb));
    for (const auto& t : f.truth) {
      r.truth.push_back(fromMsg(t));
      // The graph's rollouts carry no truth depth (docs/outputs.md: completeness is null there);
      // the context's alone would make a figure of the first frames only.
      r.truth.back().depth_m = cv::Mat();
    }
  }
  return r;
}

CheckpointId WorldModelClient::checkpoint() {
  valerant::Checkpoint srv;
  checkpoint_.call(srv);
  current_ = srv.response.checkpoint_id;
  return current_;
}

void WorldModelClient::restore(CheckpointId id) {
  valerant::Restore srv;
  srv.request.checkpoint_id = id;
  restore_.call(srv);
  current_ = id;
}

void WorldModelClient::dropCheckpoint(CheckpointId id) {
  valerant::Drop srv;
  srv.request.checkpoint_id = id;
  drop_.call(srv);
}

Rollout WorldModelClient::rollout(const ActionSequence& actions) {
  valerant::RolloutGoal goal;
  goal.checkpoint_id = current_;
  goal.candidate = actions.name;
  const auto state = rollout_.sendGoalAndWait(goal, ::ros::Duration(rollout_timeout_s_));
  const auto result = rollout_.getResult();
  if (state != actionlib::SimpleClientGoalState::SUCCEEDED || !result)
    throw InputError("rollout of " + actions.name,
                     state.toString() + (result && !result->status.empty() ? ": " + result->status : std::string()));
  Rollout r;
  r.id = result->rollout_id;
  r.candidate = actions.name;
  for (const auto& t : result->truth) r.truth.push_back(fromMsg(t));
  return r;
}

void WorldModelClient::commit(const Rollout& rollout) {
  valerant::Commit srv;
  srv.request.rollout_id = rollout.id;
  srv.request.candidate = rollout.candidate;
  commit_.call(srv);
  current_ = 0;
}

void WorldModelClient::reset() {
  valerant::Reset srv;
  reset_.call(srv);
  current_ = 0;
}

}  // namespace valerant::bridge
