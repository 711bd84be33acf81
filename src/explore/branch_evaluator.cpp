#include "valerant/explore/branch_evaluator.h"

#include <chrono>

#include "valerant/explore/depth_collision.h"
#include "valerant/explore/point_cloud_collision.h"

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

StageSeconds& StageSeconds::operator+=(const StageSeconds& o) {
  render += o.render, slam += o.slam, floor += o.floor;
  collision += o.collision, policy += o.policy, fusion += o.fusion;
  return *this;
}

BranchOutcome evaluateBranch(Rollout rollout, bool rotation_only, const BranchContext& ctx, const Config& config) {
  BranchOutcome out{std::move(rollout), rotation_only, ctx.committed_slam->branch(), *ctx.committed_floor};
  BranchVerdict& v = out.verdict;
  v.candidate = out.rollout.candidate;
  v.rotation_only = rotation_only;
  Stopwatch watch;

  std::vector<FloorPlane> samples;
  std::vector<DepthSample> depth_samples;
  std::vector<HeightedPoint> points;
  out.centres.push_back(ctx.start_centre);
  for (size_t i = 0; i < out.rollout.frames.size(); ++i) {
    SlamInput in;
    in.rgb = out.rollout.frames[i];
    if (i < out.rollout.truth.size()) in.truth = &out.rollout.truth[i];
    const TrackedFrame f = out.slam->track(in);
    out.seconds.slam += watch.lap();
    if (f.state == TrackingState::kLost) v.slam_lost = true;
    FloorPlane floor;
    if (f.keyframe && out.slam->keyframeCount() > 0) {
      KeyframeCloud kf = out.slam->keyframeClouds(out.slam->keyframeCount() - 1).front();
      floor = out.floor.update(kf.points, f.camera_to_map);
      for (const auto& p : kf.points)
        points.push_back({p.position.cast<double>(), floor.normalisedHeight(p.position.cast<double>()), p.confidence});
      out.keyframes.push_back(std::move(kf));
      out.keyframe_floors.push_back(floor);
    } else {
      floor = out.floor.at(f.camera_to_map);
    }
    out.seconds.floor += watch.lap();
    out.poses.push_back(f.camera_to_map);
    out.centres.push_back(f.camera_to_map.translation());
    samples.push_back(floor);
    const double central = f.depth.empty() ? std::nan("") : centralMeanDepth(f.depth, config.collision.center_fraction);
    depth_samples.push_back({central, floor, f.camera_to_map.linear().col(2)});
    out.seconds.collision += watch.lap();
  }

  if (config.collision.pointcloud_enabled) {
    const PointCloudCollision pc = detectPointCloudCollision(points, samples, config.collision, rotation_only);
    v.collision_pc = pc.collision;
    v.occupied_max = pc.occupied_max;
  }
  const DepthCollision dc = detectDepthCollision(depth_samples, config.collision, ctx.d_fwd_normalised);
  v.min_near_ratio = dc.min_near_ratio;
  if (config.collision.depth_enabled) v.collision_depth = dc.collision;
  out.seconds.collision += watch.lap();

  const CoverageTerms terms = ctx.grid->score(out.centres);
  v.c_new = terms.c_new;
  v.c_front = terms.c_front;
  v.coverage = terms.coverage;
  v.progress = terms.progress;
  Cell start;
  ctx.grid->cellOf(ctx.start_centre, start);
  v.enters_failed = ctx.failed->enters(terms.cells, start);
  out.seconds.policy += watch.lap();
  return out;
}

}  // namespace valerant
