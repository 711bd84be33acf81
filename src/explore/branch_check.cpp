#include "valerant/explore/branch_check.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "valerant/explore/clean_prefix.h"

namespace valerant {

BranchCheck::BranchCheck(const Config& config, CommittedSteps committed)
    : config_(config.collision),
      committed_(config.collision.previous_steps > 0 ? std::move(committed) : CommittedSteps{}),
      d_fwd_normalised_(config.world.d_fwd_units / config.world.eye_height_units),
      fov_x_deg_(config.world.fov_x_deg) {}

namespace {
// The depth views keep every second pixel a side: the visual depth is swept at half
// resolution and scaled up by nearest pixel, so nothing it measured is lost.
constexpr int kDepthViewShrink = 2;
}  // namespace

void BranchCheck::add(const TrackedFrame& frame, const KeyframeCloud* keyframe, const FloorPlane& floor) {
  if (frame.state == TrackingState::kLost && first_lost_ < 0) first_lost_ = static_cast<int>(samples_.size());
  if (keyframe) keyframes_.push_back({samples_.size(), keyframe->points});
  samples_.push_back(floor);
  poses_.push_back(frame.camera_to_map);
  central_depths_.push_back(frame.depth.empty() ? std::nan("")
                                                : centralMeanDepth(frame.depth, config_.center_fraction));
  if (config_.see_through_frames > 0 && frame.state != TrackingState::kLost && !frame.depth.empty()) {
    depth_views_.push_back(depthViewOf(frame.camera_to_map, frame.depth, frame.confidence, config_.min_confidence,
                                       kDepthViewShrink));
  }
}

std::vector<FloorPlane> BranchCheck::floors() const {
  std::vector<FloorPlane> out = samples_;
  size_t first = 0;
  while (first < out.size() && !out[first].known) ++first;
  if (first == out.size()) return out;
  const FloorPlane& f = out[first];
  const Eigen::Vector3d normal_camera = poses_[first].linear().transpose() * f.n;
  const double distance = f.cameraHeight();
  for (size_t i = 0; i < first; ++i) {
    FloorPlane& p = out[i];
    p.c = poses_[i].translation();
    p.n = (poses_[i].linear() * normal_camera).normalized();
    p.q = p.c - distance * p.n;
    p.known = true;
    p.reliable = false;
  }
  return out;
}

std::optional<ReachableBox> BranchCheck::reachOfAll(const std::vector<FloorPlane>& floors, double radius) const {
  const FloorPlane* reference = referenceSample(floors);
  if (!reference) return std::nullopt;
  const BodyReach frame(*reference);
  double u_min = std::numeric_limits<double>::infinity(), u_max = -u_min;
  auto extend = [&](const Eigen::Vector3f& position) {
    const Eigen::Vector3d x = position.cast<double>();
    if (!x.allFinite()) return;  // never counted
    const double u = frame.along(x);
    u_min = std::min(u_min, u);
    u_max = std::max(u_max, u);
  };
  for (const KeyframePoints& kf : keyframes_)
    for (const auto& p : kf.points) extend(p.position);
  for (const auto& step : committed_)
    for (const auto& p : *step) extend(p.position);
  if (!(u_min <= u_max)) return std::nullopt;
  const auto box = frame.spanOfAll(floors, radius, u_min, u_max);
  if (!box) return std::nullopt;
  return ReachableBox{frame, *box};
}

BranchVerdict BranchCheck::finish(const std::string& candidate, bool rotation_only) const {
  BranchVerdict v;
  v.candidate = candidate;
  v.rotation_only = rotation_only;
  v.slam_lost = first_lost_ >= 0;
  const std::vector<FloorPlane> floors = this->floors();
  if (floors.empty() || !floors.back().known) {
    v.floor_unknown = !rotation_only;
    v.min_near_ratio = std::numeric_limits<double>::infinity();
    return v;
  }
  int first_unsafe = first_lost_, reference = first_lost_ - 1;  // a lost frame's pose is no reference
  auto unsafeAt = [&](int frame) {
    if (frame < 0 || (first_unsafe >= 0 && frame >= first_unsafe)) return;
    first_unsafe = reference = frame;
  };
  if (config_.pointcloud_enabled) {
    // The stepped body follows one support height along the branch: every height from
    // one datum, the branch's first floor (step_support.h).
    const FloorPlane& start = floors.front();
    const bool stepped = config_.step_height > 0;
    // The cylinder counts only confident body-level points (bodyCylinderCounts); the
    // stepped body looks at every point. Dropping the others here, before they are
    // copied, keeps the counts and spares most of the committed steps' points (their
    // floors and ceilings), which every candidate of a step went through.
    auto counted = [&](double h, float confidence) {
      return stepped || countedInBody(h, confidence, config_);
    };
    // Eq. 6 at rho; a prefix also keeps prefix_clearance from the branch's points: rho
    // leaves the Quake III hull (0.30 to 0.42 eye heights from its axis) touching what
    // eq. 6 passes.
    // counts[i] holds the counts at radii[i]: rho first, then the optional radii.
    std::vector<double> radii = {config_.body_radius};
    const size_t prefix_radius = radii.size();
    if (config_.prefix_commits) radii.push_back(config_.prefix_clearance);
    const size_t end_radius = radii.size();
    const bool end_checked = config_.end_clearance > 0 && !rotation_only;
    if (end_checked) radii.push_back(config_.end_clearance);
    const std::optional<ReachableBox> reach = reachOfAll(floors, *std::max_element(radii.begin(), radii.end()));
    auto reachable = [&](const Eigen::Vector3d& x) { return !reach || reach->contains(x); };
    std::vector<HeightedPoint> points;
    for (const KeyframePoints& kf : keyframes_)
      for (const auto& p : kf.points) {
        const Eigen::Vector3d x = p.position.cast<double>();
        if (!reachable(x)) continue;
        const FloorPlane& datum = stepped ? start : floors[kf.frame];
        const double h = datum.normalisedHeight(x);
        if (counted(h, p.confidence)) points.push_back({x, h, p.confidence});
      }
    if (start.cameraHeight() > 0) {
      const double radius = config_.body_radius * start.cameraHeight();
      // Committed heights from each point's own keyframe's floor (committed_points.h),
      // unless the stepped body measures everything from the branch's first floor.
      const bool own_floor = config_.committed_heights == "own_floor" && !stepped;
      for (const auto& step : committed_)
        for (const auto& p : *step) {
          const Eigen::Vector3d x = p.position.cast<double>();
          if (start.axisDistanceSquared(x) <= radius * radius) {  // beside the body already
            v.start_occupied += countedInBody(start.normalisedHeight(x), p.confidence, config_);
            continue;
          }
          if (!reachable(x)) continue;
          const bool own = own_floor && std::isfinite(p.h);
          const double h = own ? static_cast<double>(p.h) : start.normalisedHeight(x);
          if (counted(h, p.confidence)) points.push_back({x, h, p.confidence});
        }
    }
    if (config_.see_through_frames > 0 && !rotation_only && !depth_views_.empty()) {
      // Every frame of a branch has one depth size.
      const cv::Mat& d = depth_views_.front().depth;
      const CameraIntrinsics k = CameraIntrinsics::fromHorizontalFov(d.cols, d.rows, fov_x_deg_);
      // Floor points (under eta_low) are no obstacle to either body and stay untested.
      const auto seen_through = [&](const HeightedPoint& p) {
        return p.h >= config_.height_low &&
               freeSpaceEvidence(p.position, depth_views_, k, config_.see_through_tolerance)
                   .seenThrough(config_.see_through_frames);
      };
      const auto kept = std::remove_if(points.begin(), points.end(), seen_through);
      v.see_through_points = static_cast<int>(points.end() - kept);
      points.erase(kept, points.end());
    }
    const std::vector<std::vector<int>> counts = bodyCylinderCounts(points, floors, config_, radii);
    const PointCloudCollision pc = pointCloudCollisionFromCounts(counts.front(), config_, rotation_only);
    v.collision_pc = pc.collision;
    v.occupied_max = pc.occupied_max;
    v.body_counts = counts.front();
    if (pc.collision) unsafeAt(pc.run_start);
    if (end_checked && !counts[end_radius].empty() && counts[end_radius].back() >= config_.n_occ) {
      // The end pose is in contact: unsafe from the start of the run of samples in
      // contact that reaches it, so a prefix stops short of that run.
      const std::vector<int>& end = counts[end_radius];
      size_t first = end.size() - 1;
      while (first > 0 && end[first - 1] >= config_.n_occ) --first;
      v.ends_in_contact = true;
      unsafeAt(static_cast<int>(first));
    }
    if (config_.prefix_commits) {
      const std::vector<int>& wide = counts[prefix_radius];
      for (size_t i = 0; i < wide.size(); ++i)
        if (wide[i] >= config_.n_occ) {
          unsafeAt(static_cast<int>(i));
          break;
        }
    }
  }
  std::vector<DepthSample> depth_samples;
  for (size_t i = 0; i < floors.size(); ++i)
    depth_samples.push_back({central_depths_[i], floors[i], poses_[i].linear().col(2)});
  const DepthCollision dc = detectDepthCollision(depth_samples, config_, d_fwd_normalised_);
  v.min_near_ratio = dc.min_near_ratio;
  if (config_.depth_enabled) {
    v.collision_depth = dc.collision;
    if (dc.collision) unsafeAt(dc.frame);
  }
  // A branch that lost track with neither test fired offers no prefix: the loss says
  // nothing about where the obstacle is (a camera inside a Quake III brush sees through
  // it, so the SLAM keeps tracking through thin walls): oa_dm3 spawn 1, oa_dm4 spawn 2.
  const bool blind_loss = v.slam_lost && !v.collision_pc && !v.collision_depth;
  if (rotation_only)
    v.prefix_frames = static_cast<int>(floors.size());
  else if (!blind_loss)
    v.prefix_frames = cleanPrefixFrames(floors, first_unsafe, reference, config_.prefix_margin,
                                        config_.prefix_min_advance);
  return v;
}

}  // namespace valerant
