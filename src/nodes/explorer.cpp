// explorer: runs exploration episodes with the same Episode code as valerant_explore,
// its world model, branch pipeline and policy proxied to the graph
// (WorldModelClient, RosBranchPipeline, ArbiterClient): the same decisions.
//   action ~explore (valerant/Explore): feedback per step; a cancel stops after the
//          current step and still writes the map; the result lists the files
//   pub    decision (valerant/Decision) per step, map_update (latched) for map_fusion,
//          camera/pose and tf map -> camera (the committed camera) at publish_rate_hz
// Output files are those of valerant_explore (writeEpisodeOutputs), plus
// decisions.jsonl line by line. With ~auto_start the node runs one episode with the
// graph's configuration and exits (launch files mark it required, so the graph ends).
// Private parameters: output_dir, overwrite, auto_start, connect_timeout_s,
// rollout_timeout_s, result_timeout_s, publish_rate_hz, spinner_threads.
#include <iostream>
#include <actionlib/server/simple_action_server.h>
#include <filesystem>
#include <geometry_msgs/PoseStamped.h>
#include <optional>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>
#include <valerant/Decision.h>
#include <valerant/ExploreAction.h>
#include <valerant/MapUpdate.h>

#include "valerant/common/error.h"
#include "valerant/common/output_file.h"
#include "valerant/eval/episode_outputs.h"
#include "valerant/eval/run_directory.h"
#include "valerant/explore/episode.h"
#include "valerant/explore/episode_json.h"
#include "valerant/map/run_map.h"
#include "valerant/ros/arbiter_client.h"
#include "valerant/ros/conversions.h"
#include "valerant/ros/graph_config.h"
#include "valerant/ros/ros_branch_pipeline.h"
#include "valerant/ros/world_model_client.h"
#include "valerant/world/action_sequence.h"
#include "valerant/world/quake3/quake3_map.h"

using namespace valerant;
namespace fs = std::filesystem;

namespace {

class Explorer {
 public:
  Explorer(::ros::NodeHandle nh, ::ros::NodeHandle pnh)
      : nh_(nh),
        document_(valerant::bridge::loadGraphConfigDocument(nh)),
        config_(valerant::bridge::explorerConfig(document_)),
        output_dir_(valerant::bridge::requiredString(pnh, "output_dir")),
        overwrite_(pnh.param("overwrite", false)),
        world_(nh, valerant::bridge::requiredDouble(pnh, "connect_timeout_s"),
               valerant::bridge::requiredDouble(pnh, "rollout_timeout_s")),
        pipeline_(nh, valerant::bridge::requiredDouble(pnh, "connect_timeout_s"),
                  valerant::bridge::requiredDouble(pnh, "result_timeout_s")),
        arbiter_(nh, valerant::bridge::requiredDouble(pnh, "connect_timeout_s")),
        server_(pnh, "explore", [this](const valerant::ExploreGoalConstPtr& goal) { onGoal(*goal); }, false) {
    decisions_ = nh.advertise<valerant::Decision>("decision", 16);
    map_update_ = nh.advertise<valerant::MapUpdate>("map_update", 1, true);
    pose_ = nh.advertise<geometry_msgs::PoseStamped>("camera/pose", 1);
    timer_ = nh.createTimer(::ros::Duration(1.0 / valerant::bridge::requiredDouble(pnh, "publish_rate_hz")),
                            [this](const ::ros::TimerEvent&) { publishPose(); });
    // Every backend names an engine map: the world itself, a recording of it, or the
    // learned world's truth shadow (unless the learned world started from a screenshot:
    // see run()).
    try {  // ground truth for the report; the engine map is only read, never rendered
      truth_map_ = quake3::loadQuake3Map(config_.world.map, config_.world.patch_level);
    } catch (const std::exception& e) {
      ROS_WARN_STREAM("explorer: no ground truth for the report: " << e.what());
    }
    server_.start();
  }

  // One episode with the graph's configuration (the ~auto_start mode); true on success.
  bool runConfigured() {
    valerant::ExploreGoal goal;
    goal.spawn = -1;
    goal.seed = -1;
    const valerant::ExploreResult result = run(goal, [] { return !::ros::ok(); });
    if (!result.error.empty()) ROS_ERROR_STREAM("explorer: " << result.error);
    return result.error.empty();
  }

 private:
  void onGoal(const valerant::ExploreGoal& goal) {
    const valerant::ExploreResult result = run(goal, [this] { return server_.isPreemptRequested() || !::ros::ok(); });
    if (!result.error.empty())
      server_.setAborted(result, result.error);
    else if (result.preempted)
      server_.setPreempted(result, "stopped after step " + std::to_string(result.steps) + "; map saved");
    else
      server_.setSucceeded(result);
  }

  // The goal's configuration: the graph's, with its budget (checked as the file's is).
  ConfigDocument configFor(const valerant::ExploreGoal& goal) const {
    if (!goal.world.empty() && goal.world != config_.world.map)
      throw InputError("world '" + goal.world + "'", "the graph runs '" + config_.world.map + "' (relaunch with map:=)");
    if (goal.spawn >= 0 && goal.spawn != config_.world.spawn)
      throw InputError("spawn " + std::to_string(goal.spawn),
                       "the graph runs spawn " + std::to_string(config_.world.spawn) + " (relaunch with spawn:=)");
    if (goal.seed >= 0 && static_cast<uint32_t>(goal.seed) != config_.world.seed)
      throw InputError("seed " + std::to_string(goal.seed),
                       "the graph runs seed " + std::to_string(config_.world.seed) + " (relaunch with seed:=)");
    ConfigDocument c = document_;
    if (goal.budget > 0) c.set("policy.budget_steps", std::to_string(goal.budget), "goal budget " + std::to_string(goal.budget));
    return c;
  }

  valerant::ExploreResult run(const valerant::ExploreGoal& goal, const std::function<bool()>& stop) {
    valerant::ExploreResult result;
    try {
      const ConfigDocument document = configFor(goal);
      const Config config = document.parse();
      const std::string out = goal.output_dir.empty() ? output_dir_ : goal.output_dir;
      prepareRunDirectory(out, overwrite_ ? RunStart::kForce : RunStart::kNew);
      saveRunConfig(out, document, false);
      world_.reset();
      Episode episode(world_, pipeline_, arbiter_, config);
      publishMap(episode, 0);
      AppendOnlyLog decisions(out + "/decisions.jsonl", false);
      nlohmann::json report = runReportHeader("explorer", config);
      SnapshotSchedule snapshots;
      RunSnapshot snapshot(out);
      while (!episode.finished() && !stop()) {
        const StepRecord r = episode.step();
        decisions.writeLine(toJson(r).dump());
        snapshotAfterStep(snapshot, episode, r, report, snapshots);
        publishStep(episode, r);
        ROS_INFO_STREAM("explorer: step " << r.step << ": "
                                          << (r.chosen >= 0
                                                  ? describeAction(r.candidates[r.chosen].verdict.candidate, config_)
                                                  : std::string("stall"))
                                          << (r.rewind ? " + rewind" : "") << " (" << r.wall_seconds << " s)");
      }
      result.preempted = !episode.finished();
      report["interrupted"] = result.preempted;
      // The learned world started from a screenshot has no level, whatever world.map says:
      // its frames come without truth, and so does the report.
      const bool no_truth = config.world.backend == "learned" && world_.context().truth.empty();
      if (no_truth) {  // as valerant_explore --image reports it: no level was explored
        report["map"] = nullptr;
        report["spawn"] = nullptr;
      }
      writeEpisodeOutputs(episode, no_truth ? nullptr : truth_map_.get(), out, true, report);
      writeRunReport(out, report);
      for (const auto& f : report["files"]) result.map_files.push_back(out + "/" + f.get<std::string>());
      result.committed_steps = static_cast<uint32_t>(episode.committedSteps());
      result.steps = static_cast<uint32_t>(episode.history().size());
      result.rewinds = static_cast<uint32_t>(episode.rewinds());
      result.map_points = report["map_points"].get<uint32_t>();
      result.statistics_json = report.dump();
      ROS_INFO_STREAM("explorer: " << result.committed_steps << " committed steps, " << result.map_points
                                   << " map points, files in " << out);
    } catch (const std::exception& e) {
      result.error = e.what();
    }
    return result;
  }

  void publishStep(const Episode& episode, const StepRecord& r) {
    valerant::Decision d;
    d.header.stamp = ::ros::Time::now();
    d.header.frame_id = "map";
    d.step = static_cast<uint32_t>(r.step);
    d.checkpoint_id = r.checkpoint;
    d.chosen = r.chosen >= 0 ? r.candidates[r.chosen].verdict.candidate : "";
    for (const auto& c : r.candidates) d.verdicts.push_back(valerant::bridge::toMsg(c.verdict, c.centres));
    d.rewind = r.rewind;
    d.rewind_to = r.rewind_to;
    d.discarded_steps = static_cast<uint32_t>(r.discarded_steps);
    d.committed_steps = static_cast<uint32_t>(episode.committedSteps());
    decisions_.publish(d);
    publishMap(episode, r.step);
    valerant::ExploreFeedback feedback;
    feedback.step = d.step;
    feedback.verdicts = d.verdicts;
    feedback.chosen = d.chosen;
    feedback.committed_steps = d.committed_steps;
    feedback.rewinds = static_cast<uint32_t>(episode.rewinds());
    if (server_.isActive()) server_.publishFeedback(feedback);
  }

  void publishMap(const Episode& episode, int step) {
    valerant::MapUpdate m;
    m.header.stamp = ::ros::Time::now();
    m.header.frame_id = "map";
    m.step = static_cast<uint32_t>(step);
    for (const auto& kf : episode.map().keyframes()) {
      m.keyframe_ids.push_back(kf->id);
      m.keyframes.push_back(valerant::bridge::toFusedCloudMsg(kf->points, "map"));
      m.keyframe_poses.push_back(valerant::bridge::toMsg(kf->camera_to_map));
    }
    for (const auto& p : episode.trajectory()) m.trajectory.push_back(valerant::bridge::toMsg(p));
    m.grid_anchor = valerant::bridge::toMsg(episode.gridAnchor(), 0);
    m.grid_heading.x = episode.gridHeading().x();
    m.grid_heading.y = episode.gridHeading().y();
    m.grid_heading.z = episode.gridHeading().z();
    for (const Cell& c : episode.failed().cells()) m.failed_cells.insert(m.failed_cells.end(), {c.first, c.second});
    map_update_.publish(m);
    std::lock_guard<std::mutex> lock(pose_mutex_);
    camera_ = episode.trajectory().back();
  }

  void publishPose() {
    std::optional<Eigen::Isometry3d> camera;
    {
      std::lock_guard<std::mutex> lock(pose_mutex_);
      camera = camera_;
    }
    if (!camera) return;
    geometry_msgs::PoseStamped pose;
    pose.header.stamp = ::ros::Time::now();
    pose.header.frame_id = "map";
    pose.pose = valerant::bridge::toPoseMsg(*camera);
    pose_.publish(pose);
    geometry_msgs::TransformStamped t;
    t.header = pose.header;
    t.child_frame_id = "camera";
    t.transform.translation.x = pose.pose.position.x;
    t.transform.translation.y = pose.pose.position.y;
    t.transform.translation.z = pose.pose.position.z;
    t.transform.rotation = pose.pose.orientation;
    tf_.sendTransform(t);
  }

  ::ros::NodeHandle nh_;
  ConfigDocument document_;  // written into every run directory (valerant_export reads it)
  Config config_;
  std::string output_dir_;
  bool overwrite_;
  valerant::bridge::WorldModelClient world_;
  valerant::bridge::RosBranchPipeline pipeline_;
  valerant::bridge::ArbiterClient arbiter_;
  std::shared_ptr<const quake3::Quake3Map> truth_map_;
  actionlib::SimpleActionServer<valerant::ExploreAction> server_;
  ::ros::Publisher decisions_, map_update_, pose_;
  tf2_ros::TransformBroadcaster tf_;
  ::ros::Timer timer_;
  std::mutex pose_mutex_;
  std::optional<Eigen::Isometry3d> camera_;
};

}  // namespace

int main(int argc, char** argv) {
  ::ros::init(argc, argv, "explorer");
  ::ros::NodeHandle nh, pnh("~");
  // Results, service answers and the action's goals arrive while an episode runs.
  ::ros::AsyncSpinner spinner(pnh.param("spinner_threads", 0));  // 0: one per core
  spinner.start();
  try {
    Explorer explorer(nh, pnh);
    if (pnh.param("auto_start", false)) {
      const bool ok = explorer.runConfigured();
      ::ros::shutdown();
      return ok ? 0 : 1;
    }
    ::ros::waitForShutdown();
  } catch (const std::exception& e) {
    std::cerr << "explorer: error: " << e.what() << std::endl;  // see ros/node_main.h
    return 1;
  }
  return 0;
}
