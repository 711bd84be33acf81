#pragma once
// The `visual` SLAM backend: monocular RGB only (SlamInput's stamp is not read). Per
// frame:
//   1. KLT feature tracks (feature_tracker.h).
//   2. With a map: RANSAC PnP against the tracked map points (pnp_tracker.h). Without
//      one, or when PnP fails: a two-view reference frame with a known pose; the
//      rotation model (rotation_model.h) gives the pose while the parallax is too small,
//      and two-view initialisation (two_view_initializer.h) starts or extends the map
//      once it is large enough. Frames tracked by rotation only set rotation_only and
//      keep the camera position; nothing is triangulated from them.
//   3. Keyframes every few frames when the baseline allows: new points triangulated
//      from each track's first keyframe (triangulation.h), then a Ceres local bundle
//      adjustment (local_bundle_adjustment.h).
//   4. After a loss, relocalisation against recent keyframes (relocalizer.h) before a
//      new map is started, so a drop down a ledge keeps the map and its scale.
//   5. Dense depth for every frame by plane sweep against nearby keyframes
//      (plane_sweep.h documents the confidence and its 4.0 cut).
//   6. With a learned depth prior (slam.depth_prior): its metric depth fills what the
//      sweep cannot see (prior_fusion.h) on keyframes and on frames without sweep
//      depth, and frames the sweep cannot triangulate (turning in place, before the
//      map starts) add cloud-only views every DepthPriorParams::view_angle_deg, so the
//      floor, both collision tests, coverage and the map see walls seen while turning.
//      keyframeClouds() lists keyframes and cloud-only views in the order they came.
// Scale is arbitrary: the first map has median scene depth 1; a map restarted after a
// rotation without shared points keeps the last median scene depth (a prior, since
// monocular scale cannot be observed across a view change without shared points).
// The map frame is the first camera's optical frame.
//
// Branching: state is a value whose keyframes, points and images are shared
// immutable objects (slam_map.h), so branch() and snapshot() copy vectors of pointers.
// Every RANSAC is seeded from `params.seed` and the frame index on the calling thread,
// so branches fed the same frames give identical results on any thread.
#include <memory>
#include <vector>

#include "valerant/config/config.h"
#include "valerant/common/depth_prior.h"
#include "valerant/slam/slam.h"
#include "valerant/slam/visual/feature_tracker.h"
#include "valerant/slam/visual/slam_map.h"
#include "valerant/slam/visual/two_view_initializer.h"
#include "valerant/config/visual_slam_config.h"

namespace valerant {

class VisualSlam : public Slam {
 public:
  // Tuned by config.visual; `prior`: the learned depth prior, shared by every branch;
  // nullptr = none.
  VisualSlam(const CameraIntrinsics& intrinsics, const SlamConfig& config,
             std::shared_ptr<const DepthPrior> prior = nullptr);

  // Throws InputError for a frame that is not CV_8UC3 of the intrinsics' size.
  TrackedFrame track(const SlamInput& input) override;
  std::unique_ptr<Slam> branch() const override;
  std::shared_ptr<const SlamState> snapshot() const override;
  void restore(const std::shared_ptr<const SlamState>& state) override;
  std::vector<KeyframeCloud> keyframeClouds(int first = 0) const override;
  int keyframeCount() const override { return static_cast<int>(state_.clouds.size()); }
  std::vector<Eigen::Isometry3d> trajectory() const override;
  CameraIntrinsics intrinsics() const override { return intrinsics_; }

 private:
  enum class Mode { kStart, kReference, kMapped };
  struct Reference {
    int frame = 0;
    Eigen::Isometry3d camera_to_map = Eigen::Isometry3d::Identity();
    cv::Mat rgb, sweep;
    int tracks_at_start = 0;
  };
  // Pixels of referenced tracks in a frame tracked from the reference, kept so the frame
  // can be re-posed by PnP once the two-view initialisation has made points.
  struct PendingFrame {
    int frame = 0;
    std::vector<std::pair<int, cv::Point2f>> pixels;  // track id, pixel
  };
  // A frame's pose relative to the keyframe that was newest when it was tracked, so
  // that bundle adjustment of that keyframe carries the frame along (absolute before
  // the first keyframe: keyframe = -1).
  struct FramePose {
    int keyframe = -1;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  };
  // A view that contributes a cloud only (no tracking, no bundle adjustment).
  struct CloudView {
    int frame = 0;
    Eigen::Isometry3d camera_to_map = Eigen::Isometry3d::Identity();
    cv::Mat rgb, depth, confidence;
  };
  // One entry of keyframeClouds(): a keyframe (index into map.keyframes) or a view.
  struct CloudEntry {
    int keyframe = -1;
    std::shared_ptr<const CloudView> view;
  };
  struct State : SlamState {
    explicit State(const FeatureTrackerParams& p) : tracker(p) {}
    visual::FeatureTracker tracker;
    visual::SlamMap map;
    Mode mode = Mode::kStart;
    Reference reference;
    std::vector<PendingFrame> pending;
    std::vector<FramePose> frames;
    cv::Mat prev_rgb, prev_sweep;
    bool rotating = false;          // the last frame was rotation only
    bool relocalizing = false;      // lost since the map was last tracked
    int keyframe_frame = 0;         // frame of the newest keyframe
    int inliers_at_keyframe = 0;
    double median_depth = 1.0;      // of the map points seen last (map units)
    double near_depth = 0.3;        // 2nd percentile of the same
    double map_per_metre = 0;       // the prior's scale (prior_fusion.h); 0 = not yet known
    std::vector<CloudEntry> clouds;
  };
  // Work of one track() call.
  struct Frame {
    int index = 0;
    cv::Mat rgb, gray, sweep;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    std::shared_ptr<visual::KeyframeImages> new_keyframe;  // not shared until track() returns
  };

  bool trackMapped(Frame& frame, TrackedFrame& out);
  bool trackReference(Frame& frame, TrackedFrame& out);
  void startReference(const Frame& frame, const Eigen::Isometry3d& pose, bool from_previous);
  void initializeMap(Frame& frame, TrackedFrame& out, const visual::TwoViewResult& two_view,
                     const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b,
                     const std::vector<size_t>& which);
  void resectPending(int reference_keyframe);
  void makeKeyframe(Frame& frame);
  void describeKeyframe(Frame& frame);
  bool relocalize(Frame& frame, TrackedFrame& out);
  void bundleAdjust(Frame& frame);
  void denseDepth(const Frame& frame, TrackedFrame& out) const;
  // Fuses the prior into `out` where it is needed; true when the frame became a
  // cloud-only view.
  bool applyPrior(const Frame& frame, TrackedFrame& out);
  void updateSceneDepth(const Eigen::Isometry3d& pose, const std::vector<int>& point_ids);
  std::shared_ptr<visual::KeyframeImages> addKeyframe(const cv::Mat& rgb, const cv::Mat& sweep, int frame_index,
                                                      const Eigen::Isometry3d& pose);
  Eigen::Isometry3d framePose(int index) const;
  int addPoint(const Eigen::Vector3d& position, const cv::Mat& rgb, const cv::Point2f& color_px,
               std::vector<visual::Observation> observations);
  void observe(int point, const visual::Observation& observation);

  CameraIntrinsics intrinsics_;
  CameraIntrinsics sweep_intrinsics_;
  SlamConfig config_;
  std::shared_ptr<const DepthPrior> prior_;
  State state_;
};

}  // namespace valerant
