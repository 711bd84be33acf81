// branch_slam (nodelet valerant/BranchSlam): the SLAM of the candidate branches named
// in ~candidates, one slot per candidate. graph.launch loads all five into the branch
// nodelet manager; distributed graphs may run one per process (nodelet standalone). Each slot serves namespace branch/<c> on its own
// callback queue and thread, so the five branches track in parallel:
//   sub  branch/<c>/frames (valerant/Frame) -> pub branch/<c>/tracked, one per frame
//   srv  branch/<c>/slam/track_context  a fresh SLAM on the world model's context
//        branch/<c>/slam/{checkpoint,restore,drop}  the committed SLAM under the world's
//        checkpoint ids
//        branch/<c>/slam/commit {rollout_id, candidate}: when the chosen candidate's slot
//        is in this process its branch state is handed over (a snapshot: the map points
//        are shared, not copied); otherwise the rollout is fetched from the world model
//        and replayed (both backends are deterministic, so every slot ends in the same state)
// Private parameters: candidates (list), connect_timeout_s.
#include <algorithm>
#include <boost/make_shared.hpp>
#include <mutex>
#include <pluginlib/class_list_macros.hpp>
#include <optional>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <ros/spinner.h>
#include <ros/topic.h>
#include <sensor_msgs/CameraInfo.h>
#include <valerant/Checkpoint.h>
#include <valerant/Commit.h>
#include <valerant/Drop.h>
#include <valerant/Frame.h>
#include <valerant/GetRollout.h>
#include <valerant/Restore.h>
#include <valerant/SlamFrame.h>
#include <valerant/TrackContext.h>

#include "valerant/common/error.h"
#include "valerant/common/joined.h"
#include "valerant/explore/branch_stages.h"
#include "valerant/explore/checkpoint_store.h"
#include "valerant/ros/conversions.h"
#include "valerant/ros/graph_config.h"
#include "valerant/ros/graph_names.h"
#include "valerant/ros/guarded.h"
#include "valerant/ros/nodelet_of.h"
#include "valerant/ros/topic_links.h"
#include "valerant/ros/service_call.h"
#include "valerant/slam/rollout_truth.h"
#include "valerant/slam/slam_factory.h"
#include "valerant/world/action_sequence.h"

using namespace valerant;
using valerant::bridge::guarded;

namespace {

// A branch's final state, handed from the chosen candidate's slot to its siblings.
struct ChosenBranch {
  RolloutId rollout_id = 0;
  CheckpointId checkpoint_id = 0;  // the committed state the branch started from
  std::shared_ptr<const SlamState> state;
};

class BranchSlot;

// What a slot may ask of the process it lives in.
class SlotHost {
 public:
  virtual ~SlotHost() = default;
  // The branch of `candidate` that tracked `rollout_id`, if that slot is in this
  // process and still holds it.
  virtual std::optional<ChosenBranch> chosenBranch(RolloutId rollout_id, const std::string& candidate) = 0;
};

class BranchSlot {
 public:
  BranchSlot(::ros::NodeHandle root, const std::string& candidate, const Config& config,
             const CameraIntrinsics& intrinsics, SlotHost& host)
      : candidate_(candidate),
        name_("branch_slam " + candidate),
        config_(config),
        intrinsics_(intrinsics),
        host_(host),
        get_rollout_(valerant::bridge::ServiceLink::to<valerant::GetRollout>(
            root, std::string(valerant::bridge::kWorldModel) + "/get_rollout")),
        spinner_(1, &queue_) {
    ::ros::NodeHandle branch(root, "branch/" + candidate);
    branch.setCallbackQueue(&queue_);
    ::ros::NodeHandle services(branch, "slam");
    tracked_ = branch.advertise<valerant::SlamFrame>("tracked", 256);
    frames_ = branch.subscribe("frames", 256, &BranchSlot::onFrame, this);
    services_ = {services.advertiseService("track_context", &BranchSlot::trackContext, this),
                 services.advertiseService("checkpoint", &BranchSlot::checkpoint, this),
                 services.advertiseService("restore", &BranchSlot::restore, this),
                 services.advertiseService("drop", &BranchSlot::drop, this),
                 services.advertiseService("commit", &BranchSlot::commit, this)};
    spinner_.start();
  }
  ~BranchSlot() { spinner_.stop(); }  // before the members its callbacks use

  const std::string& candidate() const { return candidate_; }
  // This slot's candidate or one of its clean prefixes (uw@31 runs on uw's slot).
  bool isOwnCandidate(const std::string& name) const {
    try {
      return baseCandidate(name) == candidate_;
    } catch (const InputError&) {
      return false;
    }
  }

  std::optional<ChosenBranch> branchOf(RolloutId rollout_id) {
    std::lock_guard<std::mutex> lock(branch_mutex_);
    if (!branch_ || branch_rollout_ != rollout_id) return std::nullopt;
    return ChosenBranch{rollout_id, branch_checkpoint_, branch_->snapshot()};
  }

 private:
  Slam& committed() {
    if (!committed_) throw InputError(name_, "no episode started (call track_context first)");
    return *committed_;
  }

  valerant::StateDigest digest() {
    const auto trajectory = committed().trajectory();
    return valerant::bridge::digest(trajectory.size(), committed_->keyframeCount(),
                                    trajectory.empty() ? Eigen::Isometry3d::Identity() : trajectory.back());
  }

  // The frame's ground truth, when it carries one, is held in truth_ while it is
  // tracked: the oracle backend reads it there.
  TrackedStep track(Slam& slam, const valerant::Frame& frame) {
    const cv::Mat rgb = valerant::bridge::fromCompressedImageMsg(frame.rgb);
    if (rgb.empty()) throw InputError("frame " + std::to_string(frame.key.index), "has no image");
    const FrameStamp stamp{frame.key.rollout_id, static_cast<int>(frame.key.index)};
    std::optional<RolloutTruth::Hold> held;
    if (!frame.truth.empty()) held.emplace(truth_->hold(stamp, valerant::bridge::fromMsg(frame.truth.front())));
    return trackStep(slam, SlamInput{rgb, stamp});
  }

  valerant::SlamFrame trackedMsg(const valerant::FrameKey& key, const TrackedStep& step, bool with_depth) const {
    // Downstream reads the raw depth only (the depth collision test), so the
    // confidence image stays home: it is the largest part of a frame.
    valerant::SlamFrame msg =
        valerant::bridge::toMsg(step.frame, step.keyframe ? &*step.keyframe : nullptr, with_depth);
    msg.header.stamp = ::ros::Time::now();
    msg.key = key;
    return msg;
  }

  void publishError(const valerant::FrameKey& key, const std::string& error) {
    ROS_ERROR_STREAM(name_ << ": rollout " << key.rollout_id << ": " << error);
    valerant::SlamFrame msg;
    msg.header.stamp = ::ros::Time::now();
    msg.key = key;
    msg.error = error;
    tracked_.publish(msg);
  }

  void onFrame(const valerant::Frame::ConstPtr& frame) {
    const valerant::FrameKey& key = frame->key;
    std::lock_guard<std::mutex> lock(branch_mutex_);
    if (key.index == 0) {
      branch_.reset();
      failed_rollout_ = 0;
      if (!isOwnCandidate(key.candidate)) {
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
      branch_checkpoint_ = key.checkpoint_id;
    }
    if (key.rollout_id == failed_rollout_) return;  // reported at its first frame
    if (!branch_ || key.rollout_id != branch_rollout_) {
      publishError(key, "frame " + std::to_string(key.index) + " of a rollout whose first frame never arrived");
      failed_rollout_ = key.rollout_id;
      return;
    }
    try {
      tracked_.publish(boost::make_shared<valerant::SlamFrame>(trackedMsg(key, track(*branch_, *frame), true)));
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

  void dropBranch() {
    std::lock_guard<std::mutex> lock(branch_mutex_);
    branch_.reset();
  }

  bool trackContext(valerant::TrackContext::Request&, valerant::TrackContext::Response& res) {
    return guarded(name_ + "/track_context", res, [&] {
      auto slam = makeSlam(config_.slam.backend, intrinsics_, config_, truth_);
      for (const auto& frame : fetch(0)) res.frames.push_back(trackedMsg(frame.key, track(*slam, frame), false));
      committed_ = std::move(slam);
      saved_.clear();
      dropBranch();
      latest_ = 0;
    });
  }

  bool checkpoint(valerant::Checkpoint::Request& req, valerant::Checkpoint::Response& res) {
    return guarded(name_ + "/checkpoint", res, [&] {
      saved_.save(req.checkpoint_id, committed().snapshot());
      latest_ = req.checkpoint_id;
      res.checkpoint_id = req.checkpoint_id;
      res.state = digest();
    });
  }

  bool restore(valerant::Restore::Request& req, valerant::Restore::Response& res) {
    return guarded(name_ + "/restore", res, [&] {
      committed().restore(saved_.at(req.checkpoint_id));
      latest_ = req.checkpoint_id;
      dropBranch();
      res.state = digest();
    });
  }

  bool drop(valerant::Drop::Request& req, valerant::Drop::Response& res) {
    return guarded(name_ + "/drop", res, [&] { saved_.drop(req.checkpoint_id); });
  }

  bool commit(valerant::Commit::Request& req, valerant::Commit::Response& res) {
    return guarded(name_ + "/commit", res, [&] {
      committed();
      const std::string rollout = "rollout " + std::to_string(req.rollout_id);
      if (const auto chosen = host_.chosenBranch(req.rollout_id, req.candidate)) {
        if (chosen->checkpoint_id != latest_) throw InputError(rollout, "was made from another checkpoint");
        committed_->restore(chosen->state);
      } else {
        const auto frames = fetch(req.rollout_id);
        if (frames.empty()) throw InputError(rollout, "has no frames");
        if (frames.front().key.candidate != req.candidate)
          throw InputError(rollout, "is not a rollout of '" + req.candidate + "'");
        if (frames.front().key.checkpoint_id != latest_) throw InputError(rollout, "was made from another checkpoint");
        for (const auto& frame : frames) track(*committed_, frame);
      }
      dropBranch();
      res.state = digest();
    });
  }

  std::string candidate_, name_;
  const Config& config_;
  CameraIntrinsics intrinsics_;
  SlotHost& host_;
  valerant::bridge::ServiceLink get_rollout_;  // track_context and replayed commits
  const std::shared_ptr<RolloutTruth> truth_ = std::make_shared<RolloutTruth>();  // read by the oracle backend
  std::unique_ptr<Slam> committed_;
  CheckpointStore<std::shared_ptr<const SlamState>> saved_;
  CheckpointId latest_ = 0;  // the checkpoint the committed state stands at
  // This step's branch; guarded because siblings read it at commit time.
  std::mutex branch_mutex_;
  std::unique_ptr<Slam> branch_;
  RolloutId branch_rollout_ = 0, failed_rollout_ = 0;
  CheckpointId branch_checkpoint_ = 0;
  ::ros::Publisher tracked_;
  ::ros::Subscriber frames_;
  std::vector<::ros::ServiceServer> services_;
  ::ros::CallbackQueue queue_;
  ::ros::AsyncSpinner spinner_;
};

class BranchSlam : public SlotHost {
 public:
  BranchSlam(::ros::NodeHandle nh, ::ros::NodeHandle pnh) : config_(valerant::bridge::loadGraphConfig(nh)) {
    std::vector<std::string> candidates;
    if (!pnh.getParam("candidates", candidates) || candidates.empty())
      throw InputError("parameter " + pnh.resolveName("candidates"), "not set (a list of candidate names)");
    const CameraIntrinsics intrinsics = waitForCamera(nh, valerant::bridge::requiredDouble(pnh, "connect_timeout_s"));
    const auto& known = candidateNames();
    for (const std::string& c : candidates) {
      if (std::find(known.begin(), known.end(), c) == known.end())
        throw InputError("parameter " + pnh.resolveName("candidates"), "names an unknown candidate '" + c + "'");
      slots_.push_back(std::make_unique<BranchSlot>(nh, c, config_, intrinsics, *this));
    }
    ROS_INFO_STREAM("branch_slam: " << config_.slam.backend << " SLAM, " << intrinsics.width << "x" << intrinsics.height
                                    << ", branches " << ::ros::names::append(nh.getNamespace(), "branch") << "/{"
                                    << joined(candidates, ",") << "}");
  }

  std::optional<ChosenBranch> chosenBranch(RolloutId rollout_id, const std::string& candidate) override {
    // Every slot asks at commit time; the first answer is kept for the rest, since
    // the chosen slot drops its branch once it has committed.
    std::lock_guard<std::mutex> lock(chosen_mutex_);
    if (chosen_ && chosen_->rollout_id == rollout_id) return chosen_;
    for (const auto& slot : slots_)
      if (slot->candidate() == baseCandidate(candidate))
        if (auto branch = slot->branchOf(rollout_id)) return chosen_ = std::move(branch);
    return std::nullopt;
  }

 private:
  static CameraIntrinsics waitForCamera(::ros::NodeHandle& nh, double timeout_s) {
    const std::string topic = std::string(valerant::bridge::kWorldModel) + "/camera_info";
    const auto info = valerant::bridge::waitForLatched<sensor_msgs::CameraInfo>(topic, nh, timeout_s);
    if (!info) throw InputError(nh.resolveName(topic), "nothing received");
    CameraIntrinsics intrinsics;
    intrinsics.width = static_cast<int>(info->width);
    intrinsics.height = static_cast<int>(info->height);
    intrinsics.fx = info->K[0], intrinsics.cx = info->K[2], intrinsics.fy = info->K[4], intrinsics.cy = info->K[5];
    return intrinsics;
  }

  Config config_;
  std::mutex chosen_mutex_;
  std::optional<ChosenBranch> chosen_;
  std::vector<std::unique_ptr<BranchSlot>> slots_;  // last: stopped before the rest goes
};

}  // namespace

namespace valerant::nodes {
using BranchSlamNodelet = valerant::bridge::NodeletOf<BranchSlam>;
}
PLUGINLIB_EXPORT_CLASS(valerant::nodes::BranchSlamNodelet, nodelet::Nodelet)
