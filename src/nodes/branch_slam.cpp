// branch_slam: the SLAM of one candidate branch, in namespace branch/<candidate>.
//   sub  frames (valerant/Frame) -> pub tracked (valerant/TrackedFrame), one per frame
//   srv  ~track_context  a fresh SLAM on the world model's context (episode start)
//        ~checkpoint ~restore ~drop  the committed SLAM under the world's checkpoint ids
//        ~commit {rollout_id, candidate}: its own branch is adopted; another
//        candidate's rollout is fetched from the world model and replayed (both
//        backends are deterministic, so every branch_slam holds the same state)
// Private parameters: candidate, connect_timeout_s.
#include <ros/ros.h>
#include <ros/topic.h>
#include <sensor_msgs/CameraInfo.h>
#include <valerant/Checkpoint.h>
#include <valerant/Commit.h>
#include <valerant/Drop.h>
#include <valerant/Frame.h>
#include <valerant/GetRollout.h>
#include <valerant/Restore.h>
#include <valerant/TrackContext.h>
#include <valerant/SlamFrame.h>

#include "valerant/common/error.h"
#include "valerant/explore/branch_stages.h"
#include "valerant/explore/checkpoint_store.h"
#include "valerant/ros/conversions.h"
#include "valerant/ros/graph_config.h"
#include "valerant/ros/graph_names.h"
#include "valerant/ros/guarded.h"
#include "valerant/ros/service_call.h"
#include "valerant/ros/node_main.h"
#include "valerant/slam/slam_factory.h"

using namespace valerant;
using valerant::bridge::guarded;

namespace {

class BranchSlam {
 public:
  BranchSlam(::ros::NodeHandle nh, ::ros::NodeHandle pnh)
      : nh_(nh),
        config_(valerant::bridge::loadGraphConfig(nh)),
        candidate_(valerant::bridge::requiredString(pnh, "candidate")),
        get_rollout_(valerant::bridge::ServiceLink::to<valerant::GetRollout>(
            nh, valerant::bridge::graphRoot(nh) + valerant::bridge::kWorldModel + "/get_rollout")) {
    const std::string root = valerant::bridge::graphRoot(nh);
    const ::ros::Duration timeout(valerant::bridge::requiredDouble(pnh, "connect_timeout_s"));
    const auto info = ::ros::topic::waitForMessage<sensor_msgs::CameraInfo>(
        root + valerant::bridge::kWorldModel + "/camera_info", nh, timeout);
    if (!info) throw InputError(root + valerant::bridge::kWorldModel + "/camera_info", "nothing received");
    intrinsics_.width = static_cast<int>(info->width);
    intrinsics_.height = static_cast<int>(info->height);
    intrinsics_.fx = info->K[0], intrinsics_.cx = info->K[2], intrinsics_.fy = info->K[4], intrinsics_.cy = info->K[5];
    tracked_ = nh.advertise<valerant::SlamFrame>("tracked", 256);
    frames_ = nh.subscribe("frames", 256, &BranchSlam::onFrame, this);
    services_ = {pnh.advertiseService("track_context", &BranchSlam::trackContext, this),
                 pnh.advertiseService("checkpoint", &BranchSlam::checkpoint, this),
                 pnh.advertiseService("restore", &BranchSlam::restore, this),
                 pnh.advertiseService("drop", &BranchSlam::drop, this),
                 pnh.advertiseService("commit", &BranchSlam::commit, this)};
    ROS_INFO_STREAM("branch_slam " << candidate_ << ": " << config_.slam.backend << " SLAM, " << intrinsics_.width << "x"
                                   << intrinsics_.height);
  }

 private:
  Slam& committed() {
    if (!committed_) throw InputError("branch_slam " + candidate_, "no episode started (call track_context first)");
    return *committed_;
  }

  valerant::StateDigest digest() {
    const auto trajectory = committed().trajectory();
    return valerant::bridge::digest(trajectory.size(), committed_->keyframeCount(),
                                 trajectory.empty() ? Eigen::Isometry3d::Identity() : trajectory.back());
  }

  static TrackedStep track(Slam& slam, const valerant::Frame& frame) {
    const cv::Mat rgb = valerant::bridge::fromImageMsg(frame.rgb);
    if (rgb.empty()) throw InputError("frame " + std::to_string(frame.key.index), "has no image");
    std::optional<FrameTruth> truth;
    if (!frame.truth.empty()) truth = valerant::bridge::fromMsg(frame.truth.front());
    return trackStep(slam, rgb, truth ? &*truth : nullptr);
  }

  valerant::SlamFrame trackedMsg(const valerant::FrameKey& key, const TrackedStep& step, bool with_depth) const {
    valerant::SlamFrame msg;
    msg.header.stamp = ::ros::Time::now();
    msg.header.frame_id = "map";
    msg.key = key;
    msg.state = toString(step.frame.state);
    msg.camera_to_map = valerant::bridge::toMsg(step.frame.camera_to_map);
    msg.keyframe = step.keyframe.has_value();
    msg.parallax_free = step.frame.rotation_only;
    // Downstream reads the raw depth only (the depth collision test), so the
    // confidence image stays home: it is the largest part of a frame.
    if (with_depth) msg.depth = valerant::bridge::toImageMsg(step.frame.depth);
    if (step.keyframe) {
      msg.keyframe_index = static_cast<uint32_t>(step.keyframe->keyframe);
      msg.keyframe_frame = static_cast<uint32_t>(step.keyframe->frame);
      msg.keyframe_pose = valerant::bridge::toMsg(step.keyframe->camera_to_map);
      msg.cloud = valerant::bridge::toCloudMsg(step.keyframe->points, "map");
    }
    return msg;
  }

  void publishError(const valerant::FrameKey& key, const std::string& error) {
    ROS_ERROR_STREAM("branch_slam " << candidate_ << ": rollout " << key.rollout_id << ": " << error);
    valerant::SlamFrame msg;
    msg.header.stamp = ::ros::Time::now();
    msg.key = key;
    msg.error = error;
    tracked_.publish(msg);
  }

  void onFrame(const valerant::Frame::ConstPtr& frame) {
    const valerant::FrameKey& key = frame->key;
    if (key.index == 0) {
      branch_.reset();
      failed_rollout_ = 0;
      if (key.candidate != candidate_) {
        publishError(key, "frames of candidate '" + key.candidate + "' reached the branch of " + candidate_);
        failed_rollout_ = key.rollout_id;
        return;
      }
      if (!committed_ || key.checkpoint_id != latest_ || !saved_.contains(key.checkpoint_id)) {
        publishError(key, "stale checkpoint " + std::to_string(key.checkpoint_id) + " (this SLAM stands at " +
                              std::to_string(latest_) + ")");
        failed_rollout_ = key.rollout_id;
        return;
      }
      branch_ = committed_->branch();
      branch_rollout_ = key.rollout_id;
    }
    if (key.rollout_id == failed_rollout_) return;  // reported at its first frame
    if (!branch_ || key.rollout_id != branch_rollout_) {
      publishError(key, "frame " + std::to_string(key.index) + " of a rollout whose first frame never arrived");
      failed_rollout_ = key.rollout_id;
      return;
    }
    try {
      tracked_.publish(trackedMsg(key, track(*branch_, *frame), true));
    } catch (const std::exception& e) {
      publishError(key, e.what());
      failed_rollout_ = key.rollout_id;
      branch_.reset();
    }
  }

  std::vector<valerant::Frame> fetch(uint64_t rollout_id) {
    valerant::GetRollout srv;
    srv.request.rollout_id = rollout_id;
    srv.request.with_images = true;
    get_rollout_.call(srv);
    return srv.response.frames;
  }

  bool trackContext(valerant::TrackContext::Request&, valerant::TrackContext::Response& res) {
    return guarded("branch_slam " + candidate_ + "/track_context", res, [&] {
      auto slam = makeSlam(config_.slam.backend, intrinsics_, config_);
      for (const auto& frame : fetch(0)) res.frames.push_back(trackedMsg(frame.key, track(*slam, frame), false));
      committed_ = std::move(slam);
      saved_.clear();
      branch_.reset();
      latest_ = 0;
    });
  }

  bool checkpoint(valerant::Checkpoint::Request& req, valerant::Checkpoint::Response& res) {
    return guarded("branch_slam " + candidate_ + "/checkpoint", res, [&] {
      saved_.save(req.checkpoint_id, committed().snapshot());
      latest_ = req.checkpoint_id;
      res.checkpoint_id = req.checkpoint_id;
      res.state = digest();
    });
  }

  bool restore(valerant::Restore::Request& req, valerant::Restore::Response& res) {
    return guarded("branch_slam " + candidate_ + "/restore", res, [&] {
      committed().restore(saved_.at(req.checkpoint_id));
      latest_ = req.checkpoint_id;
      branch_.reset();
      res.state = digest();
    });
  }

  bool drop(valerant::Drop::Request& req, valerant::Drop::Response& res) {
    return guarded("branch_slam " + candidate_ + "/drop", res, [&] { saved_.drop(req.checkpoint_id); });
  }

  bool commit(valerant::Commit::Request& req, valerant::Commit::Response& res) {
    return guarded("branch_slam " + candidate_ + "/commit", res, [&] {
      committed();
      if (req.candidate == candidate_ && branch_ && branch_rollout_ == req.rollout_id) {
        committed_ = std::move(branch_);
      } else {
        const auto frames = fetch(req.rollout_id);
        if (frames.empty()) throw InputError("rollout " + std::to_string(req.rollout_id), "has no frames");
        if (frames.front().key.candidate != req.candidate)
          throw InputError("rollout " + std::to_string(req.rollout_id), "is not a rollout of '" + req.candidate + "'");
        if (frames.front().key.checkpoint_id != latest_)
          throw InputError("rollout " + std::to_string(req.rollout_id), "was made from another checkpoint");
        for (const auto& frame : frames) track(*committed_, frame);
      }
      branch_.reset();
      res.state = digest();
    });
  }

  ::ros::NodeHandle nh_;
  Config config_;
  std::string candidate_;
  valerant::bridge::ServiceLink get_rollout_;  // replays other candidates' committed rollouts
  CameraIntrinsics intrinsics_;
  std::unique_ptr<Slam> committed_;
  CheckpointStore<std::shared_ptr<const SlamState>> saved_;
  CheckpointId latest_ = 0;           // the checkpoint the committed state stands at
  std::unique_ptr<Slam> branch_;      // this step's branch
  RolloutId branch_rollout_ = 0, failed_rollout_ = 0;
  ::ros::Publisher tracked_;
  ::ros::Subscriber frames_;
  std::vector<::ros::ServiceServer> services_;
};

}  // namespace

int main(int argc, char** argv) { return valerant::bridge::spinNode<BranchSlam>(argc, argv, "branch_slam"); }
