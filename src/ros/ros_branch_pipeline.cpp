#include "valerant/ros/ros_branch_pipeline.h"

#include <valerant/Checkpoint.h>
#include <valerant/Commit.h>
#include <valerant/Drop.h>
#include <valerant/FloorAt.h>
#include <valerant/FloorContext.h>
#include <valerant/Reset.h>
#include <valerant/Restore.h>
#include <valerant/TrackContext.h>

#include "valerant/ros/conversions.h"
#include "valerant/ros/graph_names.h"
#include "valerant/ros/service_call.h"
#include "valerant/ros/topic_links.h"
#include "valerant/world/action_sequence.h"

namespace valerant::bridge {
namespace {

std::string slamService(const std::string& candidate, const std::string& leaf) {
  return branchName(candidate, "slam/" + leaf);
}
std::string floorService(const std::string& leaf) { return std::string(kFloorEstimator) + "/" + leaf; }
std::string checkerService(const std::string& leaf) { return std::string(kCollisionChecker) + "/" + leaf; }

// The tracked frames' poses, keyframes and floors as a BranchResult.
void addFrame(const valerant::SlamFrame& t, const valerant::Floor* floor, BranchResult& out) {
  out.poses.push_back(fromMsg(t.camera_to_map));
  if (t.keyframe) {
    out.keyframes.push_back(keyframeFromMsg(t));
    if (floor) out.keyframe_floors.push_back(fromMsg(*floor));
  }
}

}  // namespace

RosBranchPipeline::RosBranchPipeline(::ros::NodeHandle nh, double connect_timeout_s, double result_timeout_s)
    : nh_(nh), result_timeout_s_(result_timeout_s) {
  addLinks<valerant::Checkpoint>(allNames("checkpoint"));
  addLinks<valerant::Restore>(allNames("restore"));
  addLinks<valerant::Drop>(allNames("drop"));
  addLinks<valerant::Commit>(allNames("commit"));
  std::vector<std::string> track_context;
  for (const std::string& c : candidateNames()) track_context.push_back(slamService(c, "track_context"));
  addLinks<valerant::TrackContext>(track_context);
  addLinks<valerant::FloorContext>({floorService("floor_context")});
  addLinks<valerant::FloorAt>({floorService("floor_at")});
  addLinks<valerant::Reset>({checkerService("reset")});
  const ::ros::Duration timeout(connect_timeout_s);
  for (const std::string& name : allNames("checkpoint"))
    if (!links_.at(name).waitForExistence(timeout))
      throw InputError("service " + nh_.resolveName(name), "not reachable (is the node running?)");
  auto subscribe = [this](size_t i) {
    return nh_.subscribe(branchName(candidateNames().at(i), "result"), 10, &RosBranchPipeline::onResult, this);
  };
  for (size_t i = 0; i < candidateNames().size(); ++i) results_.push_back(subscribe(i));
  connectInputs(results_, subscribe, connect_timeout_s, "explorer");
}

template <class Service>
void RosBranchPipeline::addLinks(const std::vector<std::string>& names) {
  for (const std::string& name : names) links_.emplace(name, ServiceLink::to<Service>(nh_, name));
}

std::vector<std::string> RosBranchPipeline::allNames(const std::string& leaf) {
  std::vector<std::string> names{floorService(leaf), checkerService(leaf)};
  for (const std::string& c : candidateNames()) names.push_back(slamService(c, leaf));
  return names;
}

template <class Service>
void RosBranchPipeline::callAll(const std::string& leaf, const typename Service::Request& request) {
  std::vector<std::future<void>> calls;
  for (const std::string& n : allNames(leaf))  // one call per link at a time
    calls.push_back(std::async(std::launch::async, [request, &link = links_.at(n)] {
      Service srv;
      srv.request = request;
      link.call(srv);
    }));
  for (auto& c : calls) c.get();  // rethrows the first failure
}

BranchResult RosBranchPipeline::start(const Rollout& context) {
  // Every branch_slam tracks the context into its committed state; they are
  // deterministic, so their answers agree and any one of them feeds the floor.
  std::vector<std::future<valerant::TrackContext>> tracks;
  for (const std::string& c : candidateNames())
    tracks.push_back(std::async(std::launch::async, [&link = links_.at(slamService(c, "track_context"))] {
      valerant::TrackContext srv;
      link.call(srv);
      return srv;
    }));
  std::vector<valerant::TrackContext> tracked;
  for (auto& t : tracks) tracked.push_back(t.get());
  for (const auto& t : tracked)
    if (t.response.frames.size() != tracked.front().response.frames.size())
      throw InputError("branch_slam nodes", "disagree on the context (different frame counts)");

  valerant::Reset reset;
  links_.at(checkerService("reset")).call(reset);

  valerant::FloorContext floor;
  floor.request.frames = tracked.front().response.frames;
  links_.at(floorService("floor_context")).call(floor);
  if (floor.response.samples.size() != floor.request.frames.size())
    throw InputError("floor_estimator", "answered the context with a wrong number of floors");

  BranchResult out;
  out.rollout = context;
  for (size_t i = 0; i < floor.request.frames.size(); ++i)
    addFrame(floor.request.frames[i], &floor.response.samples[i].floor, out);
  out.floor_reliable = !floor.response.samples.empty() && floor.response.samples.back().has_reliable;
  return out;
}

void RosBranchPipeline::checkpoint(CheckpointId id) {
  valerant::Checkpoint::Request request;
  request.checkpoint_id = id;
  callAll<valerant::Checkpoint>("checkpoint", request);
}

void RosBranchPipeline::restore(CheckpointId id) {
  valerant::Restore::Request request;
  request.checkpoint_id = id;
  callAll<valerant::Restore>("restore", request);
}

void RosBranchPipeline::drop(CheckpointId id) {
  valerant::Drop::Request request;
  request.checkpoint_id = id;
  callAll<valerant::Drop>("drop", request);
}

void RosBranchPipeline::onResult(const valerant::CandidateResult::ConstPtr& msg) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    received_[msg->key.rollout_id] = msg;
  }
  arrived_.notify_all();
}

std::future<BranchResult> RosBranchPipeline::evaluate(Rollout rollout, bool rotation_only,
                                                      std::vector<size_t> /*keep_after: every branch is tracked whole*/) {
  return std::async(std::launch::async, &RosBranchPipeline::waitForResult, this, std::move(rollout), rotation_only);
}

BranchResult RosBranchPipeline::waitForResult(Rollout rollout, bool rotation_only) {
  valerant::CandidateResult::ConstPtr msg;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    const bool ok = arrived_.wait_for(lock, std::chrono::duration<double>(result_timeout_s_),
                                      [&] { return received_.count(rollout.id) > 0; });
    if (!ok)
      throw InputError("rollout " + std::to_string(rollout.id) + " (" + rollout.candidate + ")",
                       "no result from collision_checker within the timeout");
    msg = received_.at(rollout.id);
    received_.erase(rollout.id);
  }
  const std::string what = "result of rollout " + std::to_string(rollout.id) + " (" + rollout.candidate + ")";
  if (!msg->error.empty()) throw InputError(what, msg->error);
  if (msg->key.candidate != rollout.candidate || msg->key.rotation_only != rotation_only)
    throw InputError(what, "belongs to another candidate (" + msg->key.candidate + ")");
  if (msg->keyframes.size() != msg->keyframe_floors.size() || msg->keyframes.size() != msg->keyframe_poses.size() ||
      msg->keyframes.size() != msg->keyframe_indices.size() || msg->keyframes.size() != msg->keyframe_frames.size())
    throw InputError(what, "keyframe arrays differ in length");

  BranchResult out;
  out.rollout = std::move(rollout);
  for (const auto& p : msg->poses) out.poses.push_back(fromMsg(p));
  for (size_t i = 0; i < msg->keyframes.size(); ++i) {
    KeyframeCloud kf;
    kf.keyframe = static_cast<int>(msg->keyframe_indices[i]);
    kf.frame = static_cast<int>(msg->keyframe_frames[i]);
    kf.camera_to_map = fromMsg(msg->keyframe_poses[i]);
    kf.points = fromCloudMsg(msg->keyframes[i]);
    out.keyframes.push_back(std::move(kf));
    out.keyframe_floors.push_back(fromMsg(msg->keyframe_floors[i]));
  }
  out.floor_reliable = msg->floor_reliable;
  out.verdict = fromMsg(msg->verdict);
  return out;
}

void RosBranchPipeline::commit(const BranchResult& chosen) {
  valerant::Commit::Request request;
  request.rollout_id = chosen.rollout.id;
  request.candidate = chosen.rollout.candidate;
  callAll<valerant::Commit>("commit", request);
}

FloorPlane RosBranchPipeline::floorAt(const Eigen::Isometry3d& camera_to_map) {
  valerant::FloorAt srv;
  srv.request.camera_to_map = toMsg(camera_to_map);
  links_.at(floorService("floor_at")).call(srv);
  return fromMsg(srv.response.floor);
}

}  // namespace valerant::bridge
