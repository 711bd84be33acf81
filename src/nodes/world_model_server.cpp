// world_model_server: serves a WorldModel (backend quake3, bag or learned) to the graph.
//   action   ~rollout {checkpoint_id, candidate}: frames stream on branch/<c>/frames as
//            lossless PNG (and raw on branch/<c>/image for viewers); the result carries
//            ids and truth poses
//   services ~checkpoint ~restore ~drop ~commit ~reset ~get_rollout
//   latched  ~camera_info, ~context (the episode's starting frames, for recordings)
//   periodic camera/image (committed view), tf gt_world -> gt_camera (engine truth, when
//            the world has it)
// Private parameters: bag, bag_prefix (bag backend), image (learned backend: start from
// this screenshot, no ground truth; empty: from the engine spawn), publish_rate_hz, frame_queue,
// wait_for_subscribers, subscriber_timeout_s. A backend that fails to load (a corrupt
// bag, an unknown map) is logged and every request is answered with that error.
#include <actionlib/server/simple_action_server.h>
#include <memory>
#include <mutex>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <tf2_ros/transform_broadcaster.h>
#include <valerant/Checkpoint.h>
#include <valerant/Commit.h>
#include <valerant/Context.h>
#include <valerant/Drop.h>
#include <valerant/Frame.h>
#include <valerant/GetRollout.h>
#include <valerant/Reset.h>
#include <valerant/Restore.h>
#include <valerant/RolloutAction.h>

#include "valerant/common/error.h"
#include "valerant/ros/bag_world.h"
#include "valerant/ros/conversions.h"
#include "valerant/ros/graph_config.h"
#include "valerant/ros/graph_names.h"
#include "valerant/ros/guarded.h"
#include "valerant/ros/node_main.h"
#include "valerant/world/quake3/units.h"
#include "valerant/world/world_factory.h"

using namespace valerant;
using valerant::bridge::guarded;

namespace {

// What the server keeps of the committed state for digests and viewers.
struct Committed {
  size_t frames = 0;
  Eigen::Isometry3d camera_to_world = Eigen::Isometry3d::Identity();
  bool has_truth = false;  // camera_to_world is the engine's (a screenshot start has none)
  cv::Mat image;
};

struct CachedRollout {
  Rollout rollout;
  CheckpointId checkpoint;
  bool rotation_only;
};

class WorldModelServer {
 public:
  WorldModelServer(::ros::NodeHandle nh, ::ros::NodeHandle pnh)
      : nh_(nh),
        pnh_(pnh),
        config_(valerant::bridge::loadGraphConfig(nh)),
        with_depth_(config_.slam.backend == "oracle"),
        rollout_server_(pnh, "rollout", false) {
    frame_queue_ = valerant::bridge::requiredInt(pnh, "frame_queue");
    wait_for_subscribers_ = valerant::bridge::requiredInt(pnh, "wait_for_subscribers");
    subscriber_timeout_s_ = valerant::bridge::requiredDouble(pnh, "subscriber_timeout_s");
    for (const std::string& c : candidateNames()) {
      frames_[c] = nh.advertise<valerant::Frame>(valerant::bridge::branchName(c, "frames"), frame_queue_);
      images_[c] = nh.advertise<sensor_msgs::Image>(valerant::bridge::branchName(c, "image"), frame_queue_);
    }
    camera_info_ = pnh.advertise<sensor_msgs::CameraInfo>("camera_info", 1, true);
    context_ = pnh.advertise<valerant::Context>("context", 1, true);
    camera_image_ = nh.advertise<sensor_msgs::Image>("camera/image", 1);
    services_ = {pnh.advertiseService("checkpoint", &WorldModelServer::checkpoint, this),
                 pnh.advertiseService("restore", &WorldModelServer::restore, this),
                 pnh.advertiseService("drop", &WorldModelServer::drop, this),
                 pnh.advertiseService("commit", &WorldModelServer::commit, this),
                 pnh.advertiseService("reset", &WorldModelServer::reset, this),
                 pnh.advertiseService("get_rollout", &WorldModelServer::getRollout, this)};
    rollout_server_.registerGoalCallback([this] { onRolloutGoal(); });
    rollout_server_.start();
    try {
      load();
    } catch (const std::exception& e) {
      load_error_ = e.what();
      ROS_ERROR_STREAM("world_model_server: " << load_error_ << " (serving errors until fixed)");
    }
    // The viewer's camera image and tf run on a queue and thread of their own: a rollout's
    // callback renders, encodes and publishes up to 97 frames, and would hold a timer on
    // the node's one spinner thread for that long.
    ::ros::NodeHandle timer_nh(nh);
    timer_nh.setCallbackQueue(&timer_queue_);
    timer_ = timer_nh.createTimer(::ros::Duration(1.0 / valerant::bridge::requiredDouble(pnh, "publish_rate_hz")),
                                  [this](const ::ros::TimerEvent&) { publishCommitted(); });
    timer_spinner_ = std::make_unique<::ros::AsyncSpinner>(1, &timer_queue_);
    timer_spinner_->start();
  }

 private:
  void load() {
    const std::string image = pnh_.param<std::string>("image", "");
    if (config_.world.backend == "bag") {
      world_ = std::make_unique<valerant::bridge::BagWorld>(valerant::bridge::requiredString(pnh_, "bag"),
                                                         valerant::bridge::requiredString(pnh_, "bag_prefix"));
    } else {  // quake3, or learned from the image or the engine spawn (the map is kept for a reset)
      world_ = makeWorld(config_, image, map_);
    }
    cache_.clear();
    saved_.clear();
    current_ = 0;
    const Rollout context = world_->context();
    Committed start;
    start.frames = context.frames.size();
    setCommitted(withRollout(start, context));
    publishCameraInfo();
    valerant::Context msg;
    msg.header.stamp = ::ros::Time::now();
    for (size_t i = 0; i < context.frames.size(); ++i) msg.frames.push_back(frameMsg(context, i, 0, "context", false));
    context_.publish(msg);
    ROS_INFO_STREAM("world_model_server: " << config_.world.backend << " world "
                                           << (image.empty() ? config_.world.map + ", spawn " + std::to_string(config_.world.spawn)
                                                             : "from screenshot " + image)
                                           << ", " << context.frames.size() << " context frames");
  }

  WorldModel& world() {
    if (!world_) throw InputError("world model", load_error_.empty() ? "not loaded" : load_error_);
    return *world_;
  }

  static Committed withRollout(Committed c, const Rollout& r) {
    if (!r.truth.empty()) {
      c.camera_to_world = r.truth.back().camera_to_world;
      c.has_truth = true;
    }
    if (!r.frames.empty()) c.image = r.frames.back();
    return c;
  }

  // Only service and action callbacks (the node's spinner thread) write committed_; the
  // timer thread reads it under the lock.
  void setCommitted(const Committed& c) {
    std::lock_guard<std::mutex> lock(committed_mutex_);
    committed_ = c;
  }

  valerant::StateDigest digest() const {
    return valerant::bridge::digest(committed_.frames, 0, committed_.camera_to_world);
  }

  void publishCameraInfo() {
    const CameraIntrinsics k = world_->intrinsics();
    sensor_msgs::CameraInfo info;
    info.header.frame_id = "camera";
    info.width = k.width;
    info.height = k.height;
    info.distortion_model = "plumb_bob";
    info.D.assign(5, 0.0);
    info.K = {k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1};
    info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    info.P = {k.fx, 0, k.cx, 0, 0, k.fy, k.cy, 0, 0, 0, 1, 0};
    camera_info_.publish(info);
  }

  valerant::Frame frameMsg(const Rollout& r, size_t i, CheckpointId checkpoint, const std::string& candidate,
                           bool rotation_only, bool with_images = true) const {
    valerant::Frame f;
    f.header.stamp = ::ros::Time::now();
    f.header.frame_id = "camera";
    f.key.checkpoint_id = checkpoint;
    f.key.rollout_id = r.id;
    f.key.candidate = candidate;
    f.key.rotation_only = rotation_only;
    f.key.index = static_cast<uint32_t>(i);
    f.key.count = static_cast<uint32_t>(r.frames.empty() ? r.truth.size() : r.frames.size());
    if (with_images && i < r.frames.size()) f.rgb = valerant::bridge::toCompressedImageMsg(r.frames[i]);
    if (i < r.truth.size()) f.truth.push_back(valerant::bridge::toMsg(r.truth[i], with_images && with_depth_));
    return f;
  }

  void onRolloutGoal() {
    const auto goal = rollout_server_.acceptNewGoal();
    valerant::RolloutResult result;
    try {
      const auto& names = candidateNames();
      if (std::find(names.begin(), names.end(), baseCandidate(goal->candidate)) == names.end())
        throw InputError("candidate '" + goal->candidate + "'", "unknown (one of uw, jw, lw, jq, lq, or e.g. uw@31)");
      if (goal->checkpoint_id == 0 || goal->checkpoint_id != current_)
        throw InputError("checkpoint " + std::to_string(goal->checkpoint_id),
                         "stale: the committed state stands at " +
                             (current_ ? "checkpoint " + std::to_string(current_) : std::string("no checkpoint")));
      const ActionSequence seq = makeActionSequence(goal->candidate, config_);
      Rollout r = world().rollout(seq);
      publishFrames(r, goal->candidate, seq.rotationOnly());
      result.rollout_id = r.id;
      result.frames = static_cast<uint32_t>(r.frames.size());
      for (const auto& t : r.truth) result.truth.push_back(valerant::bridge::toMsg(t, false));
      result.status = "ok";
      cache_[r.id] = {std::move(r), current_, seq.rotationOnly()};
      rollout_server_.setSucceeded(result);
    } catch (const std::exception& e) {
      result.status = e.what();
      ROS_ERROR_STREAM("world_model_server: rollout: " << e.what());
      rollout_server_.setAborted(result, result.status);
    }
  }

  void publishFrames(const Rollout& r, const std::string& candidate, bool rotation_only) {
    const std::string slot = baseCandidate(candidate);  // a clean prefix streams on its candidate's branch
    ::ros::Publisher& pub = frames_.at(slot);
    ::ros::Publisher& images = images_.at(slot);
    // Frames sent before a subscriber (branch_slam, a recorder) is connected are lost.
    const ::ros::WallTime deadline = ::ros::WallTime::now() + ::ros::WallDuration(subscriber_timeout_s_);
    while (static_cast<int>(pub.getNumSubscribers()) < wait_for_subscribers_ && ::ros::WallTime::now() < deadline)
      ::ros::WallDuration(0.01).sleep();
    if (static_cast<int>(pub.getNumSubscribers()) < wait_for_subscribers_)
      ROS_WARN_STREAM("world_model_server: " << pub.getTopic() << " has " << pub.getNumSubscribers() << " of "
                                             << wait_for_subscribers_ << " expected subscribers");
    valerant::RolloutFeedback feedback;
    for (size_t i = 0; i < r.frames.size(); ++i) {
      pub.publish(frameMsg(r, i, current_, candidate, rotation_only));
      if (images.getNumSubscribers() > 0) images.publish(valerant::bridge::toImageMsg(r.frames[i]));
      feedback.frames_done = static_cast<uint32_t>(i + 1);
      rollout_server_.publishFeedback(feedback);
    }
  }

  bool checkpoint(valerant::Checkpoint::Request&, valerant::Checkpoint::Response& res) {
    return guarded("world_model/checkpoint", res, [&] {
      const CheckpointId id = world().checkpoint();
      saved_[id] = committed_;
      current_ = id;
      cache_.clear();
      res.checkpoint_id = id;
      res.state = digest();
    });
  }

  bool restore(valerant::Restore::Request& req, valerant::Restore::Response& res) {
    return guarded("world_model/restore", res, [&] {
      world().restore(req.checkpoint_id);
      setCommitted(saved_.at(req.checkpoint_id));
      current_ = req.checkpoint_id;
      cache_.clear();
      res.state = digest();
    });
  }

  bool drop(valerant::Drop::Request& req, valerant::Drop::Response& res) {
    return guarded("world_model/drop", res, [&] {
      world().dropCheckpoint(req.checkpoint_id);
      saved_.erase(req.checkpoint_id);
    });
  }

  bool commit(valerant::Commit::Request& req, valerant::Commit::Response& res) {
    return guarded("world_model/commit", res, [&] {
      const auto it = cache_.find(req.rollout_id);
      if (it == cache_.end() || it->second.checkpoint != current_)
        throw InputError("rollout " + std::to_string(req.rollout_id), "unknown or stale (made before the latest checkpoint)");
      if (!req.candidate.empty() && req.candidate != it->second.rollout.candidate)
        throw InputError("rollout " + std::to_string(req.rollout_id), "is a rollout of " + it->second.rollout.candidate +
                                                                           ", not of " + req.candidate);
      world().commit(it->second.rollout);
      Committed next = committed_;
      next.frames += it->second.rollout.frames.size();
      setCommitted(withRollout(next, it->second.rollout));
      current_ = 0;
      res.state = digest();
    });
  }

  bool reset(valerant::Reset::Request&, valerant::Reset::Response& res) {
    return guarded("world_model/reset", res, [&] {
      world_.reset();
      load_error_.clear();
      try {
        load();
      } catch (const std::exception& e) {
        load_error_ = e.what();
        throw;
      }
      res.state = digest();
    });
  }

  bool getRollout(valerant::GetRollout::Request& req, valerant::GetRollout::Response& res) {
    return guarded("world_model/get_rollout", res, [&] {
      if (req.rollout_id == 0) {
        const Rollout context = world().context();
        for (size_t i = 0; i < std::max(context.frames.size(), context.truth.size()); ++i)
          res.frames.push_back(frameMsg(context, i, 0, "context", false, req.with_images));
        return;
      }
      const auto it = cache_.find(req.rollout_id);
      if (it == cache_.end())
        throw InputError("rollout " + std::to_string(req.rollout_id), "unknown (made before the latest checkpoint?)");
      const CachedRollout& c = it->second;
      for (size_t i = 0; i < c.rollout.frames.size(); ++i)
        res.frames.push_back(frameMsg(c.rollout, i, c.checkpoint, c.rollout.candidate, c.rotation_only, req.with_images));
    });
  }

  void publishCommitted() {
    Committed committed;
    {
      std::lock_guard<std::mutex> lock(committed_mutex_);
      committed = committed_;
    }
    const ::ros::Time now = ::ros::Time::now();
    if (!committed.image.empty() && camera_image_.getNumSubscribers() > 0) {
      sensor_msgs::Image image = valerant::bridge::toImageMsg(committed.image);
      image.header.stamp = now;
      image.header.frame_id = "camera";
      camera_image_.publish(image);
    }
    if (!committed.has_truth) return;  // no engine pose to show
    geometry_msgs::TransformStamped t;
    t.header.stamp = now;
    t.header.frame_id = "gt_world";
    t.child_frame_id = "gt_camera";
    const Eigen::Vector3d p = committed.camera_to_world.translation() / quake3::kUnitsPerMetre;
    const Eigen::Quaterniond q(committed.camera_to_world.linear());
    t.transform.translation.x = p.x(), t.transform.translation.y = p.y(), t.transform.translation.z = p.z();
    t.transform.rotation.x = q.x(), t.transform.rotation.y = q.y(), t.transform.rotation.z = q.z();
    t.transform.rotation.w = q.w();
    tf_.sendTransform(t);
  }

  ::ros::NodeHandle nh_, pnh_;
  Config config_;
  bool with_depth_;  // only the oracle SLAM reads the depth truth
  int frame_queue_ = 0, wait_for_subscribers_ = 0;
  double subscriber_timeout_s_ = 0;
  std::shared_ptr<const quake3::Quake3Map> map_;
  std::unique_ptr<WorldModel> world_;
  std::string load_error_;
  CheckpointId current_ = 0;
  std::map<RolloutId, CachedRollout> cache_;  // rollouts since the latest checkpoint
  std::mutex committed_mutex_;
  Committed committed_;
  std::map<CheckpointId, Committed> saved_;
  actionlib::SimpleActionServer<valerant::RolloutAction> rollout_server_;
  std::map<std::string, ::ros::Publisher> frames_, images_;
  ::ros::Publisher camera_info_, context_, camera_image_;
  std::vector<::ros::ServiceServer> services_;
  tf2_ros::TransformBroadcaster tf_;
  // Declared last: the spinner thread stops before the timer and the state it reads go.
  ::ros::CallbackQueue timer_queue_;
  ::ros::Timer timer_;
  std::unique_ptr<::ros::AsyncSpinner> timer_spinner_;
};

}  // namespace

int main(int argc, char** argv) { return valerant::bridge::spinNode<WorldModelServer>(argc, argv, "world_model_server"); }
