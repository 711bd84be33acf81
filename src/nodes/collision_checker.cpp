// collision_checker (nodelet valerant/CollisionChecker): judges every branch (paper eqs. 6 and 7) with BranchCheck.
//   sub branch/<c>/floor (valerant/FloorSample) -> pub branch/<c>/result
//   (valerant/BranchResult) once the rollout's last frame is in, or at its first error.
//   srv ~reset  a new episode: no committed step
//       ~checkpoint ~restore ~drop  the latest committed steps' points (CommittedPoints,
//       counted by BranchCheck), under the world's checkpoint ids
//       ~commit  the committed candidate's keyframe points join them
#include <optional>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <valerant/CandidateResult.h>
#include <valerant/Checkpoint.h>
#include <valerant/Commit.h>
#include <valerant/Drop.h>
#include <valerant/FloorSample.h>
#include <valerant/Reset.h>
#include <valerant/Restore.h>

#include "valerant/common/error.h"
#include "valerant/explore/branch_check.h"
#include "valerant/explore/checkpoint_store.h"
#include "valerant/explore/committed_points.h"
#include "valerant/ros/conversions.h"
#include "valerant/ros/graph_config.h"
#include "valerant/ros/graph_names.h"
#include "valerant/ros/guarded.h"
#include "valerant/ros/nodelet_of.h"
#include "valerant/ros/topic_links.h"
#include "valerant/world/action_sequence.h"

using namespace valerant;
using valerant::bridge::guarded;

namespace {

struct Branch {
  std::optional<BranchCheck> check;
  valerant::CandidateResult result;
  std::vector<uint32_t> keyframe_at;  // frame index of each keyframe in `result`
  bool done = true;                   // nothing in flight
};

class CollisionChecker {
 public:
  CollisionChecker(::ros::NodeHandle nh, ::ros::NodeHandle pnh) : config_(valerant::bridge::loadGraphConfig(nh)) {
    for (const std::string& c : candidateNames())
      results_[c] = nh.advertise<valerant::CandidateResult>(valerant::bridge::branchName(c, "result"), 16);
    subscribe_ = [this, nh](size_t i) mutable {
      const std::string c = candidateNames().at(i);
      return nh.subscribe<valerant::FloorSample>(valerant::bridge::branchName(c, "floor"), 256,
                                                 [this, c](const valerant::FloorSample::ConstPtr& msg) { onSample(c, *msg); });
    };
    for (size_t i = 0; i < candidateNames().size(); ++i) samples_.push_back(subscribe_(i));
    services_ = {pnh.advertiseService("reset", &CollisionChecker::reset, this),
                 pnh.advertiseService("checkpoint", &CollisionChecker::checkpoint, this),
                 pnh.advertiseService("restore", &CollisionChecker::restore, this),
                 pnh.advertiseService("drop", &CollisionChecker::drop, this),
                 pnh.advertiseService("commit", &CollisionChecker::commit, this)};
  }

 private:
  void fail(const std::string& candidate, const valerant::FrameKey& key, const std::string& error) {
    ROS_ERROR_STREAM("collision_checker: " << candidate << " rollout " << key.rollout_id << ": " << error);
    Branch& b = branches_[candidate];
    b.result = {};
    b.result.header.stamp = ::ros::Time::now();
    b.result.key = key;
    b.result.error = error;
    results_.at(candidate).publish(b.result);
    b.done = true;
    b.check.reset();
  }

  void onSample(const std::string& candidate, const valerant::FloorSample& s) {
    const valerant::SlamFrame& t = s.tracked;
    Branch& b = branches_[candidate];
    if (!t.error.empty()) {
      if (!(b.done && b.result.key.rollout_id == t.key.rollout_id && !b.result.error.empty()))
        fail(candidate, t.key, t.error);  // once per rollout
      return;
    }
    if (t.key.index == 0) {
      b.check.emplace(config_, committed_.points());
      b.result = {};
      b.keyframe_at.clear();
      b.result.key = t.key;
      b.done = false;
    } else if (b.done || t.key.rollout_id != b.result.key.rollout_id) {
      if (!b.done || b.result.key.rollout_id != t.key.rollout_id)
        fail(candidate, t.key, "frame " + std::to_string(t.key.index) + " of a rollout whose first frame never arrived");
      return;
    }
    try {
      if (t.key.index != b.check->frames()) throw InputError("frame " + std::to_string(t.key.index), "out of order");
      const TrackedFrame frame = valerant::bridge::trackedFrameFromMsg(t);
      std::optional<KeyframeCloud> keyframe;
      if (t.keyframe) keyframe = valerant::bridge::keyframeFromMsg(t);
      b.check->add(frame, keyframe ? &*keyframe : nullptr, valerant::bridge::fromMsg(s.floor));
      b.result.poses.push_back(t.camera_to_map);
      if (t.keyframe) {
        b.result.keyframes.push_back(t.cloud);
        b.result.keyframe_indices.push_back(t.keyframe_index);
        b.result.keyframe_frames.push_back(t.keyframe_frame);
        b.result.keyframe_poses.push_back(t.keyframe_pose);
        b.result.keyframe_floors.push_back(s.floor);
        b.keyframe_at.push_back(t.key.index);
      }
      b.result.floor_reliable = s.has_reliable;
      if (t.key.index + 1 == t.key.count) {
        b.result.header.stamp = ::ros::Time::now();
        b.result.header.frame_id = "map";
        b.result.verdict = valerant::bridge::toMsg(b.check->finish(t.key.candidate, t.key.rotation_only));
        // Keyframes made before the branch's first floor get it back-filled, exactly as
        // in the in-process pipeline (BranchCheck::floors), so both fuse the same map.
        const std::vector<FloorPlane> floors = b.check->floors();
        for (size_t k = 0; k < b.keyframe_at.size(); ++k) {
          const std_msgs::Header header = b.result.keyframe_floors[k].header;
          b.result.keyframe_floors[k] = valerant::bridge::toMsg(floors[b.keyframe_at[k]], b.keyframe_at[k]);
          b.result.keyframe_floors[k].header = header;
        }
        results_.at(candidate).publish(b.result);
        judged_[t.key.rollout_id] = b.result;
        b.done = true;
        b.check.reset();
      }
    } catch (const std::exception& e) {
      fail(candidate, t.key, e.what());
    }
  }

  bool reset(valerant::Reset::Request&, valerant::Reset::Response& res) {
    return guarded("collision_checker/reset", res, [&] {
      // An episode starts here: its first results must not be lost to a link still being set up.
      valerant::bridge::connectInputs(samples_, subscribe_, valerant::bridge::kTopicLinkTimeoutS, "collision_checker");
      committed_ = CommittedPoints(config_.collision, frameIntrinsics());
      saved_.clear();
      branches_.clear();
      judged_.clear();
    });
  }

  bool checkpoint(valerant::Checkpoint::Request& req, valerant::Checkpoint::Response& res) {
    return guarded("collision_checker/checkpoint", res, [&] {
      saved_.save(req.checkpoint_id, committed_);
      judged_.clear();  // a new step: rollouts of the last one can no longer be committed
      res.checkpoint_id = req.checkpoint_id;
    });
  }

  bool restore(valerant::Restore::Request& req, valerant::Restore::Response& res) {
    return guarded("collision_checker/restore", res, [&] {
      committed_ = saved_.at(req.checkpoint_id);
      judged_.clear();
    });
  }

  bool drop(valerant::Drop::Request& req, valerant::Drop::Response& res) {
    return guarded("collision_checker/drop", res, [&] { saved_.drop(req.checkpoint_id); });
  }

  bool commit(valerant::Commit::Request& req, valerant::Commit::Response& res) {
    return guarded("collision_checker/commit", res, [&] {
      const auto it = judged_.find(req.rollout_id);
      if (it == judged_.end())
        throw InputError("rollout " + std::to_string(req.rollout_id) + " of '" + req.candidate + "'",
                         "no such branch was judged since the latest checkpoint");
      const valerant::CandidateResult& judged = it->second;
      if (judged.keyframe_poses.size() != judged.keyframes.size())
        throw InputError("rollout " + std::to_string(req.rollout_id) + " of '" + req.candidate + "'",
                         std::to_string(judged.keyframes.size()) + " keyframe clouds but " +
                             std::to_string(judged.keyframe_poses.size()) + " keyframe poses");
      std::vector<KeyframeCloud> keyframes;
      for (size_t k = 0; k < judged.keyframes.size(); ++k)
        keyframes.push_back({0, 0, valerant::bridge::fromMsg(judged.keyframe_poses[k]),
                             valerant::bridge::fromCloudMsg(judged.keyframes[k])});
      std::vector<FloorPlane> floors;
      for (const auto& floor : judged.keyframe_floors) floors.push_back(valerant::bridge::fromMsg(floor));
      committed_.add(keyframes, floors);
      judged_.clear();
    });
  }

  // The camera the graph's frames are rendered with (world.width x height, fov_x_deg):
  // carving rebuilds the committed keyframes' depth views with it (committed_points.h).
  CameraIntrinsics frameIntrinsics() const {
    return CameraIntrinsics::fromHorizontalFov(config_.world.width, config_.world.height, config_.world.fov_x_deg);
  }

  Config config_;
  CommittedPoints committed_{config_.collision, frameIntrinsics()};  // counted by every branch's BranchCheck
  CheckpointStore<CommittedPoints> saved_;
  std::map<std::string, Branch> branches_;  // in flight, one per candidate's branch
  // Every rollout judged since the latest checkpoint: a step may judge several on one
  // candidate's branch (clean prefixes, short actions) and commit any of them.
  std::map<RolloutId, valerant::CandidateResult> judged_;
  std::map<std::string, ::ros::Publisher> results_;
  std::vector<::ros::Subscriber> samples_;
  valerant::bridge::Resubscribe subscribe_;
  std::vector<::ros::ServiceServer> services_;
};

}  // namespace

namespace valerant::nodes {
using CollisionCheckerNodelet = valerant::bridge::NodeletOf<CollisionChecker>;
}
PLUGINLIB_EXPORT_CLASS(valerant::nodes::CollisionCheckerNodelet, nodelet::Nodelet)
