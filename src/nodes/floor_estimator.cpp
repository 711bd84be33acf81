// floor_estimator (nodelet valerant/FloorEstimator): the robust floor estimator (RF)
// of every branch.
//   sub  branch/<c>/tracked -> pub branch/<c>/floor (valerant/FloorSample, the tracked
//        frame with its floor), for the five candidates
//   srv  ~floor_context  a fresh estimator on the tracked context (episode start)
//        ~checkpoint ~restore ~drop ~commit  the committed estimator, under the world's
//        checkpoint ids; commit adopts the committed candidate's branch estimator
//        ~floor_at  the committed floor at a pose (anchors the coverage grid)
#include <boost/make_shared.hpp>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <valerant/Checkpoint.h>
#include <valerant/Commit.h>
#include <valerant/Drop.h>
#include <valerant/FloorAt.h>
#include <valerant/FloorContext.h>
#include <valerant/FloorSample.h>
#include <valerant/Restore.h>
#include <valerant/SlamFrame.h>

#include "valerant/common/error.h"
#include "valerant/explore/branch_stages.h"
#include "valerant/explore/checkpoint_store.h"
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
  std::optional<FloorEstimator> floor;  // the branch's copy of the committed estimator
  bool failed = false;
};

class FloorEstimatorNode {
 public:
  FloorEstimatorNode(::ros::NodeHandle nh, ::ros::NodeHandle pnh) : config_(valerant::bridge::loadGraphConfig(nh)) {
    for (const std::string& c : candidateNames())
      floors_[c] = nh.advertise<valerant::FloorSample>(valerant::bridge::branchName(c, "floor"), 256);
    subscribe_ = [this, nh](size_t i) mutable {
      const std::string c = candidateNames().at(i);
      return nh.subscribe<valerant::SlamFrame>(valerant::bridge::branchName(c, "tracked"), 256,
                                               [this, c](const valerant::SlamFrame::ConstPtr& msg) { onTracked(c, *msg); });
    };
    for (size_t i = 0; i < candidateNames().size(); ++i) tracked_.push_back(subscribe_(i));
    services_ = {pnh.advertiseService("floor_context", &FloorEstimatorNode::floorContext, this),
                 pnh.advertiseService("checkpoint", &FloorEstimatorNode::checkpoint, this),
                 pnh.advertiseService("restore", &FloorEstimatorNode::restore, this),
                 pnh.advertiseService("drop", &FloorEstimatorNode::drop, this),
                 pnh.advertiseService("commit", &FloorEstimatorNode::commit, this),
                 pnh.advertiseService("floor_at", &FloorEstimatorNode::floorAt, this)};
  }

 private:
  FloorEstimator& committed() {
    if (!committed_) throw InputError("floor_estimator", "no episode started (call floor_context first)");
    return *committed_;
  }

  // One frame through an estimator: InputError for a NaN pose or a broken cloud.
  valerant::FloorSample sample(FloorEstimator& floor, const valerant::SlamFrame& msg) {
    const TrackedFrame frame = valerant::bridge::trackedFrameFromMsg(msg);
    std::optional<KeyframeCloud> keyframe;
    if (msg.keyframe) {
      keyframe = valerant::bridge::keyframeFromMsg(msg);
      if (keyframe->points.empty())
        ROS_WARN_STREAM("floor_estimator: " << msg.key.candidate << " frame " << msg.key.index
                                            << ": keyframe with an empty cloud, floor propagated");
    }
    const FloorPlane plane = floorStep(floor, frame, keyframe ? &*keyframe : nullptr);
    valerant::FloorSample out;
    out.tracked = msg;
    out.floor = valerant::bridge::toMsg(plane, msg.key.index);
    out.floor.header = msg.header;
    out.has_reliable = floor.hasReliable();
    return out;
  }

  void publishError(const std::string& candidate, const valerant::SlamFrame& msg, const std::string& error) {
    ROS_ERROR_STREAM("floor_estimator: " << candidate << " rollout " << msg.key.rollout_id << ": " << error);
    valerant::FloorSample out;
    out.tracked.header = msg.header;
    out.tracked.key = msg.key;
    out.tracked.error = error;
    floors_.at(candidate).publish(out);
  }

  void onTracked(const std::string& candidate, const valerant::SlamFrame& msg) {
    const RolloutId rollout = msg.key.rollout_id;
    if (!msg.error.empty()) {  // an upstream failure travels on to the explorer
      branches_[rollout].failed = true;
      publishError(candidate, msg, msg.error);
      return;
    }
    if (msg.key.index == 0) {
      if (!committed_) {
        publishError(candidate, msg, "no episode started");
        branches_[rollout] = {std::nullopt, true};
        return;
      }
      if (msg.key.checkpoint_id != latest_) {
        publishError(candidate, msg, "stale checkpoint " + std::to_string(msg.key.checkpoint_id) +
                                         " (the floor estimator stands at " + std::to_string(latest_) + ")");
        branches_[rollout] = {*committed_, true};
        return;
      }
      branches_[rollout] = {*committed_, false};
    } else if (!branches_.count(rollout)) {
      publishError(candidate, msg, "frame " + std::to_string(msg.key.index) + " of a rollout whose first frame never arrived");
      branches_[rollout] = {std::nullopt, true};
      return;
    }
    Branch& b = branches_.at(rollout);
    if (b.failed) return;
    try {
      floors_.at(candidate).publish(boost::make_shared<valerant::FloorSample>(sample(*b.floor, msg)));
    } catch (const std::exception& e) {
      b.failed = true;
      publishError(candidate, msg, e.what());
    }
  }

  bool floorContext(valerant::FloorContext::Request& req, valerant::FloorContext::Response& res) {
    return guarded("floor_estimator/floor_context", res, [&] {
      if (req.frames.empty()) throw InputError("context", "has no frames");
      // An episode starts here: its first frames must not be lost to a link still being set up.
      valerant::bridge::connectInputs(tracked_, subscribe_, valerant::bridge::kTopicLinkTimeoutS, "floor_estimator");
      FloorEstimator floor =
          startFloorEstimator(config_, valerant::bridge::fromMsg(req.frames.front().camera_to_map));
      for (const auto& f : req.frames) res.samples.push_back(sample(floor, f));
      committed_ = floor;
      saved_.clear();
      branches_.clear();
      latest_ = 0;
    });
  }

  bool checkpoint(valerant::Checkpoint::Request& req, valerant::Checkpoint::Response& res) {
    return guarded("floor_estimator/checkpoint", res, [&] {
      saved_.save(req.checkpoint_id, committed());
      latest_ = req.checkpoint_id;
      branches_.clear();  // a new step: rollouts of the last one can no longer be committed
      res.checkpoint_id = req.checkpoint_id;
    });
  }

  bool restore(valerant::Restore::Request& req, valerant::Restore::Response& res) {
    return guarded("floor_estimator/restore", res, [&] {
      committed_ = saved_.at(req.checkpoint_id);
      latest_ = req.checkpoint_id;
      branches_.clear();
    });
  }

  bool drop(valerant::Drop::Request& req, valerant::Drop::Response& res) {
    return guarded("floor_estimator/drop", res, [&] { saved_.drop(req.checkpoint_id); });
  }

  bool commit(valerant::Commit::Request& req, valerant::Commit::Response& res) {
    return guarded("floor_estimator/commit", res, [&] {
      committed();
      const auto it = branches_.find(req.rollout_id);
      if (it == branches_.end() || it->second.failed)
        throw InputError("rollout " + std::to_string(req.rollout_id) + " of '" + req.candidate + "'",
                         "no such branch was estimated since the latest checkpoint");
      committed_ = *it->second.floor;
      branches_.clear();
    });
  }

  bool floorAt(valerant::FloorAt::Request& req, valerant::FloorAt::Response& res) {
    return guarded("floor_estimator/floor_at", res, [&] {
      res.floor = valerant::bridge::toMsg(committed().at(valerant::bridge::fromMsg(req.camera_to_map)), 0);
      res.floor.header.stamp = ::ros::Time::now();
    });
  }

  Config config_;
  std::optional<FloorEstimator> committed_;
  CheckpointStore<FloorEstimator> saved_;
  CheckpointId latest_ = 0;
  // Every rollout estimated since the latest checkpoint: a step may judge several on one
  // candidate's branch (clean prefixes, short actions) and commit any of them.
  std::map<RolloutId, Branch> branches_;
  std::map<std::string, ::ros::Publisher> floors_;
  std::vector<::ros::Subscriber> tracked_;
  valerant::bridge::Resubscribe subscribe_;
  std::vector<::ros::ServiceServer> services_;
};

}  // namespace

namespace valerant::nodes {
using FloorEstimatorNodelet = valerant::bridge::NodeletOf<FloorEstimatorNode>;
}
PLUGINLIB_EXPORT_CLASS(valerant::nodes::FloorEstimatorNodelet, nodelet::Nodelet)
