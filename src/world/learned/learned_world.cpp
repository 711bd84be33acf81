#include "valerant/world/learned/learned_world.h"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "valerant/common/error.h"
#include "valerant/config/package_dir.h"

namespace valerant {

WorldModelNet loadWorldModelNet(const Config& config) {
  const LearnedWorldConfig& l = config.world.learned;
  const WorldWarp warp = parseWorldWarp(l.warp);
  // The prior runs at the net's size: that is what the pose_anchor training read.
  std::shared_ptr<const DepthPrior> prior;
  if (warp == WorldWarp::kPoseAnchor)
    prior = std::make_shared<const DepthPrior>(packageFilePath(l.depth_prior_model), cv::Size(l.width, l.height));
  return WorldModelNet(packageFilePath(l.model), l.width, l.height, l.context_frames, warp, config.world.fov_x_deg,
                       std::move(prior));
}

cv::Mat readScreenshot(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(path, "screenshot file does not exist");
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path, "screenshot is not a file");
  const cv::Mat bgr = cv::imread(path, cv::IMREAD_COLOR);
  if (bgr.empty())
    throw InputError(path, "not an image OpenCV " CV_VERSION " can read (empty, truncated or not PNG / JPEG / ...)");
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  return rgb;
}

std::unique_ptr<LearnedWorld> LearnedWorld::fromScreenshot(WorldModelNet net, const cv::Mat& rgb,
                                                           const Config& config) {
  if (rgb.empty() || rgb.type() != CV_8UC3)
    throw InputError("screenshot", "must be a non-empty CV_8UC3 RGB image, got a " + std::to_string(rgb.cols) + "x" +
                                       std::to_string(rgb.rows) + " " + cv::typeToString(rgb.type()));
  return std::unique_ptr<LearnedWorld>(new LearnedWorld(std::move(net), rgb, std::nullopt, nullptr, config));
}

std::unique_ptr<LearnedWorld> LearnedWorld::fromSpawn(WorldModelNet net, std::shared_ptr<const quake3::Quake3Map> map,
                                                      const Config& config) {
  auto shadow = std::make_unique<quake3::Quake3World>(std::move(map), config);
  const Rollout start = shadow->context();
  const cv::Mat view = start.frames.back();
  const FrameTruth truth = start.truth.back();
  return std::unique_ptr<LearnedWorld>(new LearnedWorld(std::move(net), view, truth, std::move(shadow), config));
}

LearnedWorld::LearnedWorld(WorldModelNet net, const cv::Mat& start_rgb, std::optional<FrameTruth> start_truth,
                           std::unique_ptr<quake3::Quake3World> shadow, const Config& config)
    : net_(std::move(net)),
      config_(config),
      intrinsics_(CameraIntrinsics::fromHorizontalFov(config.world.width, config.world.height, config.world.fov_x_deg)),
      shadow_(std::move(shadow)) {
  cv::Mat start;
  cv::resize(start_rgb, start, cv::Size(net_.width(), net_.height()), 0, 0, cv::INTER_AREA);
  // A single view is the whole context, repeated; the shown context is that one frame.
  state_.net_frames.assign(net_.contextFrames(), start);
  state_.anchor = net_.startAnchor(start);
  state_.shown.push_back(shownFrame(start));
  if (start_truth) state_.shown_truth.push_back(*start_truth);
}

cv::Mat LearnedWorld::shownFrame(const cv::Mat& net_frame) const {
  cv::Mat shown;
  cv::resize(net_frame, shown, cv::Size(config_.world.width, config_.world.height), 0, 0, cv::INTER_LINEAR);
  return shown;
}

void LearnedWorld::push(State& state, const cv::Mat& net_frame, const cv::Mat& shown, const FrameTruth* truth) const {
  const size_t k = static_cast<size_t>(net_.contextFrames());
  state.net_frames.push_back(net_frame);
  while (state.net_frames.size() > k) state.net_frames.pop_front();
  state.shown.push_back(shown);
  while (state.shown.size() > k) state.shown.pop_front();
  if (truth) {
    state.shown_truth.push_back(*truth);
    while (state.shown_truth.size() > k) state.shown_truth.pop_front();
  }
}

Rollout LearnedWorld::context() const {
  Rollout r;
  r.candidate = "context";
  r.frames.assign(state_.shown.begin(), state_.shown.end());
  r.truth.assign(state_.shown_truth.begin(), state_.shown_truth.end());
  return r;
}

CheckpointId LearnedWorld::checkpoint() {
  const CheckpointId id = next_checkpoint_++;
  // Frames are never written after they are made: copying the deques shares them.
  checkpoints_[id] = Saved{state_, shadow_ ? shadow_->checkpoint() : 0};
  return id;
}

void LearnedWorld::restore(CheckpointId id) {
  auto it = checkpoints_.find(id);
  if (it == checkpoints_.end()) throw InputError("checkpoint " + std::to_string(id), "unknown or already dropped");
  if (shadow_) shadow_->restore(it->second.shadow);
  state_ = it->second.state;
  pending_.clear();
}

void LearnedWorld::dropCheckpoint(CheckpointId id) {
  auto it = checkpoints_.find(id);
  if (it == checkpoints_.end()) return;
  if (shadow_) shadow_->dropCheckpoint(it->second.shadow);
  checkpoints_.erase(it);
}

Rollout LearnedWorld::rollout(const ActionSequence& actions) {
  Rollout r;
  r.id = next_rollout_++;
  r.candidate = actions.name;
  Pending pending{state_, 0};
  // The engine moves the same way first: its truth goes with the generated frames.
  Rollout truth;
  if (shadow_) {
    truth = shadow_->rollout(actions);
    pending.shadow = truth.id;
  }
  for (size_t i = 0; i < actions.steps.size(); ++i) {
    const std::vector<cv::Mat> window(pending.end.net_frames.begin(), pending.end.net_frames.end());
    const cv::Mat next = net_.next(window, actions.steps[i], pending.end.anchor);
    const cv::Mat shown = shownFrame(next);
    push(pending.end, next, shown, shadow_ ? &truth.truth[i] : nullptr);
    r.frames.push_back(shown);
  }
  r.truth = std::move(truth.truth);
  pending_[r.id] = std::move(pending);
  return r;
}

void LearnedWorld::commit(const Rollout& rollout) {
  auto it = pending_.find(rollout.id);
  if (it == pending_.end())
    throw InputError("rollout " + std::to_string(rollout.id),
                     "was not made from the current committed state (stale after a commit or restore)");
  if (shadow_) {
    Rollout shadow_rollout;
    shadow_rollout.id = it->second.shadow;
    shadow_->commit(shadow_rollout);
  }
  state_ = std::move(it->second.end);
  pending_.clear();
}

}  // namespace valerant
