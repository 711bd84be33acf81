#include "valerant/slam/visual/visual_slam.h"

#include <algorithm>
#include <limits>
#include <map>
#include <opencv2/imgproc.hpp>
#include <unordered_map>

#include "valerant/common/error.h"
#include "valerant/slam/oracle_slam.h"
#include "valerant/slam/visual/local_bundle_adjustment.h"
#include "valerant/slam/visual/pinhole.h"
#include "valerant/slam/visual/plane_sweep.h"
#include "valerant/slam/visual/prior_fusion.h"
#include "valerant/slam/visual/pnp_tracker.h"
#include "valerant/slam/visual/relocalizer.h"
#include "valerant/slam/visual/rotation_model.h"
#include "valerant/slam/visual/triangulation.h"
#include "valerant/slam/visual/two_view_initializer.h"

namespace valerant {

using visual::KeyframeImages;
using visual::MapPoint;
using visual::Observation;
using visual::Track;

namespace {

constexpr size_t kMaxPendingFrames = 30;
// A new triangulation takes its scale from this many map points it shares with the
// map, else from this many points with a prior depth.
constexpr size_t kMinScalePoints = 5;
constexpr int kMinPriorScalePoints = 10;

double quantile(std::vector<double> v, double q) {
  const size_t i = std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(i), v.end());
  return v[i];
}

// OpenCV's RANSACs draw from the calling thread's RNG: reseed it per frame so a branch
// gives the same result whatever thread runs it and whatever ran there before.
void seedRng(uint64_t seed, int frame) {
  const uint64_t mixed = (seed + 1) * 0x9E3779B97F4A7C15ULL + static_cast<uint64_t>(frame);
  cv::setRNGSeed(static_cast<int>(mixed >> 33));
}

cv::Mat unknown(const cv::Size& size, float value) { return cv::Mat(size, CV_32F, cv::Scalar(value)); }

}  // namespace

VisualSlam::VisualSlam(const CameraIntrinsics& intrinsics, const SlamConfig& config,
                       std::shared_ptr<const DepthPrior> prior)
    : intrinsics_(intrinsics),
      sweep_intrinsics_(visual::downsampled(intrinsics, std::max(1, config.visual.sweep.downsample))),
      config_(config),
      prior_(std::move(prior)),
      state_(config.visual.tracker) {
  if (intrinsics.width < 16 || intrinsics.height < 16 || !(intrinsics.fx > 0) || !(intrinsics.fy > 0))
    throw InputError("visual SLAM intrinsics", "need a positive focal length and an image of at least 16x16");
  const PlaneSweepParams& sweep = config.visual.sweep;
  if (sweep.downsample < 1 || sweep.min_planes < 4 || sweep.max_planes < sweep.min_planes || sweep.sources < 1)
    throw InputError("slam.visual.sweep", "needs downsample >= 1, 4 <= min_planes <= max_planes, sources >= 1");
}

TrackedFrame VisualSlam::track(const SlamInput& input) {
  if (input.rgb.type() != CV_8UC3 || input.rgb.cols != intrinsics_.width || input.rgb.rows != intrinsics_.height)
    throw InputError("SLAM input frame", "must be 8-bit RGB of " + std::to_string(intrinsics_.width) + "x" +
                                             std::to_string(intrinsics_.height));
  State& s = state_;
  Frame frame;
  frame.index = static_cast<int>(s.frames.size());
  frame.rgb = input.rgb.clone();  // kept by keyframes: must not alias the caller's buffer
  cv::cvtColor(frame.rgb, frame.gray, cv::COLOR_RGB2GRAY);
  frame.sweep = visual::sweepImage(frame.gray, config_.visual.sweep);
  seedRng(config_.visual.seed, frame.index);

  s.tracker.track(frame.gray);
  const Eigen::Isometry3d last = s.frames.empty() ? Eigen::Isometry3d::Identity() : framePose(frame.index - 1);
  frame.pose = last;
  TrackedFrame out;
  bool ok = false;
  if (static_cast<int>(s.tracker.tracks().size()) >= config_.visual.keyframe.min_tracks) {
    if (s.mode == Mode::kMapped) {
      ok = trackMapped(frame, out);
      if (!ok) startReference(frame, last, true);
    }
    if (!ok && s.mode == Mode::kReference) ok = trackReference(frame, out);
  }
  if (!ok) {
    // Nothing to track against (first frame) or tracking failed: restart from here at
    // the last known pose. Only a first frame with usable corners is not a loss.
    const bool first = s.frames.empty();
    frame.pose = last;
    startReference(frame, last, false);
    out = TrackedFrame();
    if (!s.map.keyframes.empty()) s.relocalizing = true;
    if (!(s.relocalizing && relocalize(frame, out)))
      out.state = first && static_cast<int>(s.tracker.tracks().size()) >= config_.visual.keyframe.min_tracks
                      ? TrackingState::kInitializing
                      : TrackingState::kLost;
  }
  out.camera_to_map = frame.pose;
  denseDepth(frame, out);
  const bool view = prior_ && out.state != TrackingState::kLost && applyPrior(frame, out);
  if (frame.new_keyframe) {
    frame.new_keyframe->depth = out.depth.clone();  // the caller may write into out.depth
    frame.new_keyframe->confidence = out.confidence.clone();
  }
  if (!out.keyframe) s.tracker.detect(frame.gray, -1);
  out.keyframe = out.keyframe || view;  // a cloud-only view is a keyframe to the caller
  s.rotating = out.rotation_only;

  FramePose record;
  record.keyframe = s.map.keyframes.empty() ? -1 : static_cast<int>(s.map.keyframes.size()) - 1;
  record.pose = record.keyframe < 0 ? frame.pose : s.map.keyframes[record.keyframe]->camera_to_map.inverse() * frame.pose;
  s.frames.push_back(record);
  s.prev_rgb = frame.rgb;
  s.prev_sweep = frame.sweep;
  return out;
}

Eigen::Isometry3d VisualSlam::framePose(int index) const {
  const FramePose& f = state_.frames[index];
  return f.keyframe < 0 ? f.pose : state_.map.keyframes[f.keyframe]->camera_to_map * f.pose;
}

std::vector<Eigen::Isometry3d> VisualSlam::trajectory() const {
  std::vector<Eigen::Isometry3d> out;
  out.reserve(state_.frames.size());
  for (size_t i = 0; i < state_.frames.size(); ++i) out.push_back(framePose(static_cast<int>(i)));
  return out;
}

bool VisualSlam::trackMapped(Frame& frame, TrackedFrame& out) {
  State& s = state_;
  auto& tracks = s.tracker.tracks();
  std::vector<cv::Point3f> object;
  std::vector<cv::Point2f> image;
  std::vector<size_t> which;
  for (size_t i = 0; i < tracks.size(); ++i) {
    const int id = tracks[i].point;
    if (id < 0 || !s.map.points[id]) continue;
    object.emplace_back(s.map.points[id]->position.cast<float>().x(), s.map.points[id]->position.cast<float>().y(),
                        s.map.points[id]->position.cast<float>().z());
    image.push_back(tracks[i].px);
    which.push_back(i);
  }
  const int n = frame.index;
  const auto pnp = visual::solvePnp(object, image, intrinsics_, config_.visual.pnp);
  if (!pnp) return false;

  // Outlier tracks slipped or were mis-triangulated: drop them.
  std::vector<char> keep(tracks.size(), 1);
  for (size_t i : which) keep[i] = 0;
  std::vector<int> inlier_ids;
  for (int j : pnp->inliers) {
    keep[which[j]] = 1;
    inlier_ids.push_back(tracks[which[j]].point);
  }
  std::vector<Track> kept;
  for (size_t i = 0; i < tracks.size(); ++i)
    if (keep[i]) kept.push_back(tracks[i]);
  tracks = std::move(kept);
  frame.pose = pnp->camera_to_map;
  updateSceneDepth(frame.pose, inlier_ids);

  // Rotation only: the camera centre moved less than a sliver of the scene depth since
  // the last frame. Its translation is then noise: hold the position. The threshold
  // doubles while already turning, so that noise does not flicker the flag.
  const double moved = (frame.pose.translation() - framePose(n - 1).translation()).norm() / s.median_depth;
  out.rotation_only = moved < config_.visual.keyframe.rotation_only_ratio * (s.rotating ? 2.0 : 1.0);
  if (out.rotation_only) frame.pose.translation() = framePose(n - 1).translation();
  out.state = TrackingState::kTracking;

  const bool due = n - s.keyframe_frame >= config_.visual.keyframe.max_interval ||
                   inlier_ids.size() < config_.visual.keyframe.min_tracked_ratio * s.inliers_at_keyframe;
  const Eigen::Vector3d newest = s.map.keyframes.back()->camera_to_map.translation();
  const double baseline = (frame.pose.translation() - newest).norm() / s.median_depth;
  if (!out.rotation_only && due && baseline >= config_.visual.keyframe.min_baseline_ratio) {
    makeKeyframe(frame);
    out.keyframe = true;
  }
  return true;
}

bool VisualSlam::trackReference(Frame& frame, TrackedFrame& out) {
  State& s = state_;
  auto& tracks = s.tracker.tracks();
  if (!s.map.keyframes.empty()) {
    // Map points may still be in view (a short PnP failure): try them first.
    const auto mapped = std::count_if(tracks.begin(), tracks.end(),
                                      [&](const Track& t) { return t.point >= 0 && s.map.points[t.point]; });
    if (mapped >= config_.visual.pnp.min_inliers && trackMapped(frame, out)) {
      s.mode = Mode::kMapped;
      s.pending.clear();
      for (Track& t : tracks) t.referenced = false;
      return true;
    }
  }
  // Lost with a map: its keyframes may come back into view.
  if (s.relocalizing && relocalize(frame, out)) return true;
  std::vector<cv::Point2f> a, b;
  std::vector<size_t> which;
  for (size_t i = 0; i < tracks.size(); ++i) {
    if (!tracks[i].referenced) continue;
    a.push_back(tracks[i].reference_px);
    b.push_back(tracks[i].px);
    which.push_back(i);
  }
  const auto rotation = visual::estimateRotation(a, b, intrinsics_, config_.visual.two_view.ransac_threshold_px,
                                                 config_.visual.keyframe.min_tracks);
  const bool parallax = !rotation || rotation->median_parallax_px >= config_.visual.two_view.rotation_parallax_px;
  std::optional<Eigen::Matrix3d> b_from_a;
  if (rotation) b_from_a = rotation->b_from_a;
  if (parallax) {
    const auto two_view = visual::initializeTwoView(a, b, intrinsics_, config_.visual.two_view);
    if (two_view && two_view->ready) {
      initializeMap(frame, out, *two_view, a, b, which);
      return true;
    }
    // Translating, but not enough yet to triangulate: the essential matrix still
    // knows the rotation better than the rotation-only model.
    if (two_view) b_from_a = two_view->b_to_a.linear().transpose();
  }
  if (!b_from_a) return false;

  // bearing_b = R bearing_a  =>  camera b's axes in the map are R_a R^T.
  frame.pose = s.reference.camera_to_map;
  frame.pose.linear() = s.reference.camera_to_map.linear() * b_from_a->transpose();
  out.rotation_only = true;
  out.state = s.map.keyframes.empty() ? TrackingState::kInitializing : TrackingState::kTracking;
  PendingFrame pending;
  pending.frame = frame.index;
  for (const Track& t : tracks)
    if (t.referenced) pending.pixels.emplace_back(t.id, t.px);
  s.pending.push_back(std::move(pending));
  if (s.pending.size() > kMaxPendingFrames) s.pending.erase(s.pending.begin());

  // A turning camera loses its reference tracks: move the reference along, unless a
  // translation is building parallax (then keep it while enough tracks remain).
  const int remaining = static_cast<int>(a.size());
  const bool stale = remaining < 2 * config_.visual.two_view.min_points ||
                     (!parallax && remaining < s.reference.tracks_at_start / 2);
  if (stale) startReference(frame, frame.pose, false);
  return true;
}

void VisualSlam::startReference(const Frame& frame, const Eigen::Isometry3d& pose, bool from_previous) {
  State& s = state_;
  s.mode = Mode::kReference;
  s.reference.frame = from_previous ? frame.index - 1 : frame.index;
  s.reference.camera_to_map = pose;
  s.reference.rgb = from_previous ? s.prev_rgb : frame.rgb;
  s.reference.sweep = from_previous ? s.prev_sweep : frame.sweep;
  if (!from_previous) s.tracker.detect(frame.gray, -1, true);
  for (Track& t : s.tracker.tracks()) {
    t.referenced = true;
    t.reference_px = from_previous ? t.prev_px : t.px;
  }
  s.reference.tracks_at_start = static_cast<int>(s.tracker.tracks().size());
}

void VisualSlam::initializeMap(Frame& frame, TrackedFrame& out, const visual::TwoViewResult& two_view,
                               const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b,
                               const std::vector<size_t>& which) {
  State& s = state_;
  auto& tracks = s.tracker.tracks();
  // Scale: from map points seen by both views if there are some; else, with the prior,
  // the map's units per metre (set by the prior since the first frame) times the
  // prior's metres at the points in frame b; else the last median scene depth (1 for
  // the first map). Without the prior's step the first map's scale was its features'
  // median depth, while the floor (and the coverage grid's cells) had the prior's
  // scale of the whole image: 3 to 5 times apart on held-out maps (docs/motion_check.md).
  const Eigen::Isometry3d reference = s.reference.camera_to_map;
  const Eigen::Isometry3d map_to_reference = reference.inverse();
  const Eigen::Isometry3d a_to_b = two_view.b_to_a.inverse();
  std::vector<double> ratios, depths, depths_b;
  std::vector<cv::Point2f> pixels_b;
  for (size_t j = 0; j < two_view.indices.size(); ++j) {
    const Track& t = tracks[which[two_view.indices[j]]];
    depths.push_back(two_view.points[j].z());
    depths_b.push_back((a_to_b * two_view.points[j]).z());
    pixels_b.push_back(b[two_view.indices[j]]);
    if (t.point >= 0 && s.map.points[t.point])
      ratios.push_back((map_to_reference * s.map.points[t.point]->position).z() / two_view.points[j].z());
  }
  std::optional<double> metres_per_unit;
  if (ratios.size() < kMinScalePoints && prior_ && s.map_per_metre > 0)
    metres_per_unit = visual::priorMetresPerUnit(pixels_b, depths_b, prior_->predict(frame.rgb).resized(frame.rgb.size()).depth_m,
                                                 config_.visual.prior.fusion, kMinPriorScalePoints);
  const double scale = ratios.size() >= kMinScalePoints ? quantile(ratios, 0.5)
                       : metres_per_unit             ? *metres_per_unit * s.map_per_metre
                                                     : s.median_depth / quantile(depths, 0.5);
  Eigen::Isometry3d b_to_a = two_view.b_to_a;
  b_to_a.translation() *= scale;
  frame.pose = reference * b_to_a;

  const int ka = static_cast<int>(s.map.keyframes.size()), kb = ka + 1;
  auto images_a = addKeyframe(s.reference.rgb, s.reference.sweep, s.reference.frame, reference);
  frame.new_keyframe = addKeyframe(frame.rgb, frame.sweep, frame.index, frame.pose);
  for (size_t j = 0; j < two_view.indices.size(); ++j) {
    const size_t k = two_view.indices[j];
    Track& t = tracks[which[k]];
    const std::vector<Observation> seen = {{ka, {a[k].x, a[k].y}}, {kb, {b[k].x, b[k].y}}};
    if (t.point >= 0 && s.map.points[t.point]) {
      for (const Observation& o : seen) observe(t.point, o);
    } else {
      t.point = addPoint(reference * (scale * two_view.points[j]), s.reference.rgb, a[k], seen);
    }
    images_a->points.push_back(t.point);
    frame.new_keyframe->points.push_back(t.point);
  }
  for (Track& t : tracks) {
    if (t.point < 0) {
      t.anchor = t.referenced ? ka : kb;
      t.anchor_px = t.referenced ? t.reference_px : t.px;
    }
    t.referenced = false;
  }
  s.mode = Mode::kMapped;
  // The reference frame is now keyframe ka: re-anchor its pose record.
  if (s.reference.frame < static_cast<int>(s.frames.size()))
    s.frames[s.reference.frame] = FramePose{ka, Eigen::Isometry3d::Identity()};
  s.tracker.detect(frame.gray, kb, true);
  bundleAdjust(frame);
  cv::Mat reference_grey;
  cv::cvtColor(s.reference.rgb, reference_grey, cv::COLOR_RGB2GRAY);
  std::vector<std::pair<int, cv::Point2f>> seen_a;
  for (size_t j = 0; j < two_view.indices.size(); ++j) {
    const Track& t = tracks[which[two_view.indices[j]]];
    if (t.point >= 0 && s.map.points[t.point]) seen_a.emplace_back(t.point, a[two_view.indices[j]]);
  }
  images_a->described = visual::describePoints(reference_grey, seen_a, config_.visual.relocalizer);
  describeKeyframe(frame);
  s.relocalizing = false;
  resectPending(ka);
  updateSceneDepth(frame.pose, frame.new_keyframe->points);
  s.keyframe_frame = frame.index;
  s.inliers_at_keyframe = static_cast<int>(frame.new_keyframe->points.size());

  // Keyframe ka was tracked without depth: sweep it against the new keyframe.
  const auto& kf_a = *s.map.keyframes[ka];
  const visual::SweepDepth d =
      visual::planeSweep({images_a->sweep, kf_a.camera_to_map}, {{frame.sweep, frame.pose}}, sweep_intrinsics_,
                         config_.visual.sweep.near_fraction * s.near_depth, config_.visual.sweep);
  cv::resize(d.depth, images_a->depth, frame.rgb.size(), 0, 0, cv::INTER_NEAREST);
  cv::resize(d.confidence, images_a->confidence, frame.rgb.size(), 0, 0, cv::INTER_NEAREST);

  out.state = TrackingState::kTracking;
  out.keyframe = true;
  out.rotation_only = false;
}

void VisualSlam::resectPending(int reference_keyframe) {
  State& s = state_;
  std::unordered_map<int, int> point_of_track;
  for (const Track& t : s.tracker.tracks())
    if (t.point >= 0 && s.map.points[t.point]) point_of_track[t.id] = t.point;
  const Eigen::Isometry3d& anchor = s.map.keyframes[reference_keyframe]->camera_to_map;
  for (const PendingFrame& p : s.pending) {
    if (p.frame <= s.reference.frame) continue;
    std::vector<cv::Point3f> object;
    std::vector<cv::Point2f> image;
    for (const auto& [id, px] : p.pixels) {
      auto it = point_of_track.find(id);
      if (it == point_of_track.end()) continue;
      const Eigen::Vector3f q = s.map.points[it->second]->position.cast<float>();
      object.emplace_back(q.x(), q.y(), q.z());
      image.push_back(px);
    }
    const auto pnp = visual::solvePnp(object, image, intrinsics_, config_.visual.pnp);
    if (pnp) s.frames[p.frame] = FramePose{reference_keyframe, anchor.inverse() * pnp->camera_to_map};
  }
  s.pending.clear();
}

void VisualSlam::makeKeyframe(Frame& frame) {
  State& s = state_;
  auto& tracks = s.tracker.tracks();
  const int n = static_cast<int>(s.map.keyframes.size());
  frame.new_keyframe = addKeyframe(frame.rgb, frame.sweep, frame.index, frame.pose);
  std::vector<int>& seen = frame.new_keyframe->points;
  std::map<int, std::vector<size_t>> by_anchor;
  for (size_t i = 0; i < tracks.size(); ++i) {
    Track& t = tracks[i];
    if (t.point >= 0 && s.map.points[t.point]) {
      observe(t.point, {n, {t.px.x, t.px.y}});
      seen.push_back(t.point);
    } else if (t.anchor >= 0 && t.anchor < n) {
      by_anchor[t.anchor].push_back(i);
    } else {
      t.anchor = n;
      t.anchor_px = t.px;
    }
  }
  const visual::TriangulationLimits limits{config_.visual.two_view.min_point_parallax_deg,
                                           config_.visual.two_view.max_reprojection_px};
  for (const auto& [anchor, indices] : by_anchor) {
    std::vector<cv::Point2f> pa, pb;
    for (size_t i : indices) {
      pa.push_back(tracks[i].anchor_px);
      pb.push_back(tracks[i].px);
    }
    const auto points =
        visual::triangulate(s.map.keyframes[anchor]->camera_to_map, frame.pose, pa, pb, intrinsics_, limits);
    for (size_t j = 0; j < indices.size(); ++j) {
      if (!points[j]) continue;
      Track& t = tracks[indices[j]];
      t.point = addPoint(points[j]->position, frame.rgb, t.px,
                         {{anchor, {pa[j].x, pa[j].y}}, {n, {pb[j].x, pb[j].y}}});
      seen.push_back(t.point);
    }
  }
  s.tracker.detect(frame.gray, n, true);
  bundleAdjust(frame);
  describeKeyframe(frame);
  s.keyframe_frame = frame.index;
  s.inliers_at_keyframe = static_cast<int>(std::count_if(
      tracks.begin(), tracks.end(), [&](const Track& t) { return t.point >= 0 && s.map.points[t.point]; }));
}

void VisualSlam::describeKeyframe(Frame& frame) {
  std::vector<std::pair<int, cv::Point2f>> seen;
  for (const Track& t : state_.tracker.tracks())
    if (t.point >= 0 && state_.map.points[t.point]) seen.emplace_back(t.point, t.px);
  frame.new_keyframe->described = visual::describePoints(frame.gray, seen, config_.visual.relocalizer);
}

bool VisualSlam::relocalize(Frame& frame, TrackedFrame& out) {
  State& s = state_;
  auto& tracks = s.tracker.tracks();
  std::vector<cv::Point2f> corners;
  for (const Track& t : tracks) corners.push_back(t.px);
  std::vector<const visual::PointDescriptors*> keyframes;
  for (int k = static_cast<int>(s.map.keyframes.size()) - 1;
       k >= 0 && static_cast<int>(keyframes.size()) < config_.visual.relocalizer.keyframes; --k)
    keyframes.push_back(&s.map.keyframes[k]->images->described);
  const auto found = visual::relocalize(frame.gray, corners, keyframes, s.map, intrinsics_, config_.visual.relocalizer,
                                        config_.visual.pnp);
  if (!found) return false;
  // Associations made before the loss are not trusted; the matches replace them.
  for (Track& t : tracks) {
    t.point = -1;
    t.anchor = -1;
    t.referenced = false;
  }
  std::vector<int> ids;
  for (const auto& [corner, id] : found->matches) {
    tracks[corner].point = id;
    ids.push_back(id);
  }
  frame.pose = found->camera_to_map;
  updateSceneDepth(frame.pose, ids);
  s.mode = Mode::kMapped;
  s.relocalizing = false;
  s.pending.clear();
  out.state = TrackingState::kTracking;
  out.rotation_only = false;
  out.keyframe = false;
  return true;
}

void VisualSlam::bundleAdjust(Frame& frame) {
  State& s = state_;
  const int n = static_cast<int>(s.map.keyframes.size());
  const int first = std::max(0, n - config_.visual.bundle_adjustment.window);
  std::map<int, const MapPoint*> points;
  for (int k = first; k < n; ++k)
    for (int id : s.map.keyframes[k]->images->points)
      if (s.map.points[id]) points[id] = s.map.points[id].get();
  std::map<int, Eigen::Isometry3d> poses;
  for (const auto& [id, point] : points)
    for (const Observation& o : point->observations) poses[o.keyframe] = s.map.keyframes[o.keyframe]->camera_to_map;
  std::set<int> free;
  for (int k = first; k < n; ++k)
    if (poses.count(k)) free.insert(k);
  // A fixed keyframe pins position and orientation. Unless a second fixed one observes
  // these points (after the first few keyframes), the monocular scale is free: it is
  // then restored afterwards, by scaling about the fixed keyframe so that the oldest
  // free keyframe keeps its distance to it (reprojection errors do not change).
  if (free.size() == poses.size()) free.erase(free.begin());
  const bool scale_free = poses.size() - free.size() < 2 && !free.empty();
  Eigen::Vector3d anchor = Eigen::Vector3d::Zero();
  double distance = 0;
  if (scale_free) {
    for (const auto& [k, pose] : poses)
      if (!free.count(k)) anchor = pose.translation();
    distance = (poses.at(*free.begin()).translation() - anchor).norm();
  }

  auto result = visual::localBundleAdjustment(poses, free, points, intrinsics_, config_.visual.bundle_adjustment);
  if (scale_free) {
    const double after = (result.poses.at(*free.begin()).translation() - anchor).norm();
    const double scale = after > 0 ? distance / after : 1.0;
    for (auto& [k, pose] : result.poses) pose.translation() = anchor + scale * (pose.translation() - anchor);
    for (auto& [id, position] : result.points) position = anchor + scale * (position - anchor);
  }
  for (const auto& [k, pose] : result.poses) {
    auto kf = std::make_shared<visual::Keyframe>(*s.map.keyframes[k]);
    kf->camera_to_map = pose;
    s.map.keyframes[k] = std::move(kf);
  }
  for (const auto& [id, position] : result.points) {
    auto p = std::make_shared<MapPoint>(*s.map.points[id]);
    p->position = position;
    s.map.points[id] = std::move(p);
  }
  for (int id : result.rejected) s.map.points[id] = nullptr;
  for (Track& t : s.tracker.tracks()) {
    if (t.point >= 0 && !s.map.points[t.point]) {
      t.point = -1;
      t.anchor = -1;
    }
  }
  frame.pose = s.map.keyframes[n - 1]->camera_to_map;
}

void VisualSlam::denseDepth(const Frame& frame, TrackedFrame& out) const {
  const State& s = state_;
  const cv::Size size = frame.rgb.size();
  out.depth = unknown(size, std::numeric_limits<float>::quiet_NaN());
  out.confidence = unknown(size, 0.f);
  if (out.state == TrackingState::kLost) return;
  // Co-visibility: how many of the map points tracked in this frame each keyframe saw.
  // A keyframe that shares few of them looks at other surfaces (or from behind a
  // ledge) and would only add false matches.
  std::map<int, int> shared;
  int tracked = 0;
  for (const Track& t : s.tracker.tracks()) {
    if (t.point < 0 || !s.map.points[t.point]) continue;
    ++tracked;
    for (const Observation& o : s.map.points[t.point]->observations) ++shared[o.keyframe];
  }
  const PlaneSweepParams& sweep = config_.visual.sweep;
  const int min_shared =
      std::max(sweep.min_shared_points, static_cast<int>(std::ceil(sweep.min_shared_ratio * tracked)));
  const Eigen::Vector3d centre = frame.pose.translation(), axis = frame.pose.linear().col(2);
  const double min_cos = std::cos(sweep.max_view_angle_deg * M_PI / 180.0);
  std::vector<visual::SweepView> sources;
  for (auto it = shared.rbegin(); it != shared.rend() && static_cast<int>(sources.size()) < sweep.sources; ++it) {
    const visual::Keyframe& kf = *s.map.keyframes[it->first];
    if (kf.images->frame == frame.index || it->second < min_shared) continue;
    const double baseline = (kf.camera_to_map.translation() - centre).norm() / s.median_depth;
    if (baseline < sweep.min_baseline_ratio || baseline > sweep.max_baseline_ratio) continue;
    if (kf.camera_to_map.linear().col(2).dot(axis) < min_cos) continue;
    sources.push_back({kf.images->sweep, kf.camera_to_map});
  }
  if (sources.empty()) return;
  const visual::SweepDepth d = visual::planeSweep({frame.sweep, frame.pose}, sources, sweep_intrinsics_,
                                                  sweep.near_fraction * s.near_depth, sweep);
  cv::resize(d.depth, out.depth, size, 0, 0, cv::INTER_NEAREST);
  cv::resize(d.confidence, out.confidence, size, 0, 0, cv::INTER_NEAREST);
}

bool VisualSlam::applyPrior(const Frame& frame, TrackedFrame& out) {
  State& s = state_;
  // Turned far enough from the last cloud to make a cloud-only view?
  bool turned = s.clouds.empty();
  if (!turned) {
    const CloudEntry& last = s.clouds.back();
    const Eigen::Isometry3d& pose =
        last.keyframe >= 0 ? s.map.keyframes[last.keyframe]->camera_to_map : last.view->camera_to_map;
    turned = pose.linear().col(2).dot(frame.pose.linear().col(2)) <
             std::cos(config_.visual.prior.view_angle_deg * M_PI / 180.0);
  }
  const bool untriangulated = out.rotation_only || s.mode != Mode::kMapped;
  const bool view = !out.keyframe && untriangulated && turned;
  const bool blind = cv::countNonZero(out.confidence > 0) == 0;  // a translation without sweep depth
  if (!(out.keyframe || view || (blind && !out.rotation_only))) return false;

  const DepthPrediction p = prior_->predict(frame.rgb).resized(frame.rgb.size());
  const PriorFusionParams& fusion = config_.visual.prior.fusion;
  if (const auto scale = visual::priorScale(out.depth, out.confidence, p.depth_m, fusion)) s.map_per_metre = *scale;
  if (!(s.map_per_metre > 0)) {
    // Before the sweep has measured the scale: the map's convention, median scene depth
    // s.median_depth (1 for a new map), applied to the prior's median.
    std::vector<double> metres;
    for (auto it = p.depth_m.begin<float>(); it != p.depth_m.end<float>(); ++it)
      if (*it > 0 && *it <= fusion.max_depth_m) metres.push_back(*it);
    if (metres.empty()) return false;
    s.map_per_metre = s.median_depth / quantile(metres, 0.5);
  }
  visual::fusePrior(out.depth, out.confidence, p.depth_m, p.log_scale, s.map_per_metre, fusion);
  if (!view) return false;
  auto v = std::make_shared<CloudView>();
  v->frame = frame.index;
  v->camera_to_map = frame.pose;
  v->rgb = frame.rgb;
  v->depth = out.depth.clone();  // the caller may write into out.depth
  v->confidence = out.confidence.clone();
  s.clouds.push_back({-1, std::move(v)});
  return true;
}

void VisualSlam::updateSceneDepth(const Eigen::Isometry3d& pose, const std::vector<int>& point_ids) {
  State& s = state_;
  const Eigen::Isometry3d map_to_camera = pose.inverse();
  std::vector<double> depths;
  for (int id : point_ids) {
    if (!s.map.points[id]) continue;
    const double z = (map_to_camera * s.map.points[id]->position).z();
    if (z > 0) depths.push_back(z);
  }
  if (depths.size() < 10) return;
  s.median_depth = quantile(depths, 0.5);
  s.near_depth = quantile(depths, 0.02);
}

std::shared_ptr<KeyframeImages> VisualSlam::addKeyframe(const cv::Mat& rgb, const cv::Mat& sweep, int frame_index,
                                                        const Eigen::Isometry3d& pose) {
  auto images = std::make_shared<KeyframeImages>();
  images->frame = frame_index;
  images->rgb = rgb;
  images->sweep = sweep;
  auto kf = std::make_shared<visual::Keyframe>();
  kf->index = static_cast<int>(state_.map.keyframes.size());
  kf->camera_to_map = pose;
  kf->images = images;
  state_.clouds.push_back({kf->index, nullptr});
  state_.map.keyframes.push_back(std::move(kf));
  return images;
}

int VisualSlam::addPoint(const Eigen::Vector3d& position, const cv::Mat& rgb, const cv::Point2f& color_px,
                         std::vector<Observation> observations) {
  auto p = std::make_shared<MapPoint>();
  p->position = position;
  const cv::Vec3b c = rgb.at<cv::Vec3b>(cvRound(color_px.y), cvRound(color_px.x));
  p->rgb = {c[0], c[1], c[2]};
  p->observations = std::move(observations);
  state_.map.points.push_back(std::move(p));
  return static_cast<int>(state_.map.points.size()) - 1;
}

void VisualSlam::observe(int point, const Observation& observation) {
  auto p = std::make_shared<MapPoint>(*state_.map.points[point]);
  p->observations.push_back(observation);
  state_.map.points[point] = std::move(p);
}

std::unique_ptr<Slam> VisualSlam::branch() const { return std::make_unique<VisualSlam>(*this); }

std::shared_ptr<const SlamState> VisualSlam::snapshot() const { return std::make_shared<State>(state_); }

void VisualSlam::restore(const std::shared_ptr<const SlamState>& state) {
  const auto* s = dynamic_cast<const State*>(state.get());
  if (!s) throw InputError("SLAM snapshot", "was not made by the visual backend");
  state_ = *s;
}

std::vector<KeyframeCloud> VisualSlam::keyframeClouds(int first) const {
  std::vector<KeyframeCloud> out;
  for (size_t i = std::max(first, 0); i < state_.clouds.size(); ++i) {
    KeyframeCloud cloud;
    cloud.keyframe = static_cast<int>(i);
    if (const auto& view = state_.clouds[i].view) {
      cloud.frame = view->frame;
      cloud.camera_to_map = view->camera_to_map;
      cloud.points = backProject(view->rgb, view->depth, view->confidence, intrinsics_, view->camera_to_map,
                                 config_.visual.sweep.downsample);
      out.push_back(std::move(cloud));
      continue;
    }
    const visual::Keyframe& kf = *state_.map.keyframes[state_.clouds[i].keyframe];
    cloud.frame = kf.images->frame;
    cloud.camera_to_map = kf.camera_to_map;
    // Every depth the plane sweep estimated, once: the sweep runs at 1/downsample
    // resolution, so a finer stride only repeats values and a coarser one (the oracle's
    // cloud_stride_px) drops them. The paper's point counts (300 floor inliers, N_occ)
    // assume MASt3R's pixel-dense clouds; thinning ours further starves the floor fit.
    if (!kf.images->depth.empty())
      cloud.points = backProject(kf.images->rgb, kf.images->depth, kf.images->confidence, intrinsics_,
                                 kf.camera_to_map, config_.visual.sweep.downsample);
    out.push_back(std::move(cloud));
  }
  return out;
}

}  // namespace valerant
