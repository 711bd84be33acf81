#pragma once
// Tuning of the visual (monocular RGB) SLAM backend: the slam.visual section of the
// configuration (config/valerant.yaml names every value; config.cpp checks its range).
// All values are [ours]: the paper uses MASt3R-SLAM and gives none of them. They were
// chosen on engine rollouts at 320x240 with a 90 deg horizontal field of view; pixel
// values are at that size. The defaults here are the shipped file's values, for code
// that builds a SLAM without a file (unit tests); a test checks that they agree.
#include <cstdint>

namespace valerant {

struct FeatureTrackerParams {
  int max_features = 400;           // tracks kept alive
  int redetect_below = 300;         // detect new corners when fewer tracks survive
  double corner_quality = 0.003;    // goodFeaturesToTrack qualityLevel (lightmapped walls are dim)
  int min_distance_px = 8;          // spacing of corners, keeps PnP and BA well spread
  int window_px = 11;               // KLT window
  int pyramid_levels = 3;           // KLT pyramid (level 3 = 1/8 size) covers fast yaw and drops
  int iterations = 10;              // KLT iterations per level (a quarter of the frame time at 20)
  double max_forward_backward_px = 0.7;  // forward-backward disagreement that drops a track
};

struct TwoViewParams {
  double ransac_threshold_px = 1.0;  // essential matrix / homography inlier distance
  int min_points = 60;               // triangulated points needed to start a map
  double min_point_parallax_deg = 1.0;   // a point with less is too depth-ambiguous to keep
  double min_median_parallax_deg = 2.0;  // the pair as a whole must have this much
  double max_reprojection_px = 2.0;      // triangulated point must reproject this close
  // Median flow left after removing the best rotation, below which the motion is
  // treated as rotation only (no triangulation attempted).
  double rotation_parallax_px = 1.5;
};

struct PnpParams {
  int min_inliers = 15;           // fewer and the frame falls back to rotation-only / lost
  double threshold_px = 2.0;      // RANSAC inlier distance
  int iterations = 100;
  double confidence = 0.99;
};

struct KeyframeParams {
  int max_interval = 6;                // frames; keeps the plane-sweep baseline short
  double min_tracked_ratio = 0.7;      // new keyframe when tracked map points fall below this share
  double min_baseline_ratio = 0.02;    // baseline / median scene depth needed for a keyframe
  // Camera displacement since the last frame, relative to the median scene depth, below
  // which a frame is rotation only (its translation is then held fixed). A forward step
  // (d_fwd / 57) is about 0.03.
  double rotation_only_ratio = 0.006;
  int min_tracks = 20;                 // fewer surviving tracks = tracking lost
};

struct BundleAdjustmentParams {
  int window = 5;               // keyframes optimised; older observers are held fixed
  double huber_px = 1.0;        // robust loss scale
  int max_iterations = 8;
  double max_error_px = 3.0;    // points reprojecting worse after BA are dropped
};

struct PlaneSweepParams {
  int downsample = 2;            // sweep at 1/2 resolution (160x120): the speed budget
  int normalise_window_px = 7;   // local mean / contrast window at sweep resolution
  double contrast_floor = 2.0;   // 8-bit levels added to the local contrast: flat areas stay flat
  int max_planes = 64;           // inverse-depth hypotheses between 0 and 1/near ...
  int min_planes = 16;
  double min_plane = 1.5;        // winners below this plane index (from infinity) get no depth: their
                                 // bracket is wider than +-33 %; on oa_dm1 they reached 130 eye heights
  double plane_step_px = 1.0;    // ... about this much border disparity apart
  int sources = 2;               // nearby keyframes compared with each frame
  int window_px = 5;             // SAD window at sweep resolution
  double truncation = 1.5;       // per-pixel |difference| cap (local contrasts): occlusions, borders
  double noise_level = 0.1;      // SAD floor (local contrasts): resampling noise
  double min_baseline_ratio = 0.04;   // source baseline / median scene depth, at least ...
  double max_baseline_ratio = 0.3;    // ... and at most (wider: occlusions, a drop down a ledge)
  double max_view_angle_deg = 50;     // source optical axis within this angle of the frame's
  double min_shared_ratio = 0.3;      // source saw at least this share of the frame's tracked map points
  int min_shared_points = 10;         // ... and at least this many
  double near_fraction = 0.4;         // nearest plane at this fraction of the 2nd-percentile point depth
  double confidence_gain = 9.0;       // see plane_sweep.h: the 4.0 cut = rival 1.4x the best cost
  double max_confidence = 20.0;
  bool simd = true;  // the AVX2 loops where the CPU has them; false: the portable ones (the same bits, slower)
};

struct RelocalizerParams {
  int patch_px = 19;          // ORB patch (the default 31 would drop a 31-pixel border at 320x240)
  float max_distance = 64;    // Hamming distance of an acceptable match (of 256 bits)
  float ratio = 0.8f;         // best / second-best distance (Lowe's ratio test)
  int keyframes = 8;          // newest keyframes searched
  int min_inliers = 30;       // PnP inliers to accept a relocalisation
};

// How the visual SLAM fuses the learned depth prior with its plane sweep (prior_fusion.h).
struct PriorFusionParams {
  double confidence_gain = 0.6;
  double max_confidence = 20.0;
  double max_depth_m = 40.0;
  double min_confidence = 4.0;   // sweep pixels trusted for the scale
  int min_scale_pixels = 200;    // fewer: keep the last scale
};

// Use of the learned depth prior (slam.depth_prior: learned), prior_fusion.h.
struct DepthPriorParams {
  PriorFusionParams fusion;
  // A frame the sweep cannot triangulate (turning in place, before the map starts)
  // becomes a cloud-only view when its optical axis has turned this far from the last
  // cloud's: a 90 deg field of view seen every 20 deg overlaps by 78 %.
  double view_angle_deg = 20.0;
};

struct VisualSlamConfig {
  FeatureTrackerParams tracker;
  TwoViewParams two_view;
  PnpParams pnp;
  KeyframeParams keyframe;
  BundleAdjustmentParams bundle_adjustment;
  PlaneSweepParams sweep;
  RelocalizerParams relocalizer;
  DepthPriorParams prior;
  uint64_t seed = 0;  // seeds every RANSAC call (together with the frame index)
};

}  // namespace valerant
