#include "valerant/explore/branch_evaluator.h"

#include <chrono>

#include "valerant/explore/branch_check.h"
#include "valerant/explore/branch_stages.h"

namespace valerant {
namespace {

class Stopwatch {
 public:
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return s;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace

BranchResult evaluateBranch(Rollout rollout, bool rotation_only, std::unique_ptr<Slam> slam, FloorEstimator floor,
                            CommittedSteps committed, const Config& config) {
  BranchResult out;
  out.rollout = std::move(rollout);
  BranchCheck check(config, std::move(committed));
  Stopwatch watch;
  std::vector<size_t> keyframe_frames;
  for (size_t i = 0; i < out.rollout.frames.size(); ++i) {
    TrackedStep step = trackStep(*slam, SlamInput{out.rollout.frames[i], {out.rollout.id, static_cast<int>(i)}});
    out.seconds.slam += watch.lap();
    const KeyframeCloud* keyframe = step.keyframe ? &*step.keyframe : nullptr;
    const FloorPlane plane = floorStep(floor, step.frame, keyframe);
    out.seconds.floor += watch.lap();
    check.add(step.frame, keyframe, plane);
    out.poses.push_back(step.frame.camera_to_map);
    if (keyframe) {
      out.keyframes.push_back(std::move(*step.keyframe));
      keyframe_frames.push_back(i);
    }
    out.seconds.collision += watch.lap();
  }
  // Keyframes made before the branch's first floor get it back-filled (BranchCheck).
  const std::vector<FloorPlane> floors = check.floors();
  for (size_t i : keyframe_frames) out.keyframe_floors.push_back(floors[i]);
  out.verdict = check.finish(out.rollout.candidate, rotation_only);
  out.seconds.collision += watch.lap();
  out.floor_reliable = floor.hasReliable();
  out.handle = std::make_shared<LocalBranch>(std::move(slam), std::move(floor));
  return out;
}

}  // namespace valerant
