#pragma once
// Typed configuration of valerant, loaded from config/valerant.yaml. Every default is
// the paper's value (appendix A) or, for the engine world, the Quake III value; the
// YAML file documents where each number comes from. Loading is strict: a missing key,
// an unknown key, a wrong type or an out-of-range value throws InputError naming the
// file (or the flag that set it) and the key.
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "valerant/config/visual_slam_config.h"

namespace valerant {

// WM-like image degradations for stress runs (all 0 = off, the default).
struct DegradationConfig {
  double noise_sigma = 0;       // additive Gaussian noise, 8-bit levels
  double blur_sigma = 0;        // Gaussian blur, pixels
  double exposure_flicker = 0;  // per-frame gain drawn from [1-x, 1+x]
  double jitter_px = 0;         // per-frame random image shift, pixels
};

// The learned world model (world/learned/world_model_net.h, docs/world_model.md): an
// ONNX next-frame predictor at its own frame size and context length.
struct LearnedWorldConfig {
  std::string model = "models/world_model.onnx";  // relative: to the package folder
  int width = 128;           // the net's frame size: OpenCV 4.6 cannot read it from the file
  int height = 96;
  int context_frames = 4;    // K frames the net sees
  std::string warp = "rotation_anchor";  // last_frame | rotation_anchor | pose_anchor: the warp the model was trained with
  // pose_anchor's depth of the first anchor (relative: to the package folder): the prior
  // the model was trained with (models/world_model.md); unused by the other warps.
  std::string depth_prior_model = "models/depth_prior.onnx";
};

struct WorldConfig {
  std::string backend = "quake3";  // quake3 | bag | learned
  std::string map = "oa_dm1";  // map name, or /path/to/file.pk3:mapname
  int spawn = 0;
  int width = 320;
  int height = 240;
  double fov_x_deg = 90;        // Quake III default cg_fov
  double d_fwd_units = 256;     // nominal displacement of one forward action (8 m)
  double eye_height_units = 50; // feet to eye: origin 24 above feet + view height 26
  double near_plane_units = 4;
  double far_plane_units = 8192;
  int patch_level = 8;          // Bezier segments per patch block edge
  double max_drop_units = 1024; // deepest drop the eye follows down
  uint32_t seed = 0;
  DegradationConfig degradation;
  LearnedWorldConfig learned;
};

struct RolloutConfig {
  int context_frames = 16;       // K
  int horizon_frames = 57;       // H for uw, jq, lq and the turn segment of jw, lw
  int turn_forward_frames = 40;  // forward segment appended to jw, lw (H = 97)
  double turn_forward_deg = 45;  // yaw of the turn segment of jw / lw
  double rotate_deg = 90;        // yaw of jq / lq
  int flow_steps = 3;            // generative backends only
  double cfg_scale = 5.0;        // generative backends only
};

struct PolicyConfig {
  std::string kind = "valerant";  // valerant (eq. 2) | random | forward | frontier (baselines)
  double lambda_cov = 1.0;
  double lambda_prog = 5.0;
  double frontier_weight = 0.5;  // C = C_new + 0.5 C_front
  int grid_cells = 128;
  int cells_per_d_fwd = 8;       // cell width = d_fwd / 8
  int budget_steps = 15;
  int step_cap_factor = 3;       // at most factor x budget steps, stalls and rewound ones included
  // [ours] A candidate whose reconstructed motion exceeds this many forward actions is
  // inadmissible: its keys move the camera at most one (uw), so more is a SLAM scale
  // runaway, which eq. 2 would otherwise reward; 0: no check (the paper).
  double max_progress = 3.0;
  // Whole-level exploration [ours] (docs/whole_level.md), off by default: at 15 steps the
  // options raised coverage on the tuning maps but not on the held-out ones; valerant_eval's
  // `whole-level` row turns them on. 0 / empty / false = the paper (config/paper.yaml).
  // Score term goal_weight * G, G the approach to the nearest reachable frontier
  // (frontier_distance.h); cells with obstacle_min_points obstacle points block the path.
  double goal_weight = 0;
  int obstacle_min_points = 3;
  // Surface layer (surface_layer.h): the largest rise in eye heights between neighbouring
  // cells the whole-level paths step over, and within one cell's surface; 0 = the flat
  // model (floor and obstacle points over each keyframe's own floor).
  double max_cell_rise = 0;
  // With the surface layer, free-space carving: a bin counts while its points number at
  // least this times the rays that crossed it (surface_layer.h); 0 = no carving.
  double surface_carving_ratio = 0;
  // When no translation (full or clean prefix) is admissible: fixed-length prefixes of
  // uw, jw, lw (frames, longest first) and shorter in-place turns (frames of jq, lq) ...
  std::vector<int> short_translation_frames;
  std::vector<int> short_turn_frames;
  // ... and the turn to the most open measured direction (open_direction.h).
  bool open_turn = false;
  // Every step, also judge the goal move: the turn and straight walk along the shortest
  // path to the nearest reachable frontier (goal_move.h), at most one forward action.
  bool goal_move = false;
  // Score term opening_weight * O of an in-place turn, O the free floor ahead of its
  // final heading in forward actions (open_direction.h).
  double opening_weight = 0;
  // A turn in place that undoes the last committed step's turn in place (turn_back.h) is
  // chosen only when nothing else is admissible.
  bool no_turn_back = false;
  // When no translation is admissible, a translation whose only objections are listed here
  // is admitted (policy.h; docs/pockets.md "Objections that give way"): of
  // kYieldableObjections, the ones whose rejections are usually wrong.
  std::vector<std::string> yielding_objections;
};

// The objections policy.yielding_objections may name, as BranchVerdict's fields: entering
// the failed region F and a short action not clear to its end. The collision tests and a
// SLAM loss never give way.
inline const std::set<std::string> kYieldableObjections = {"enters_failed", "short_unclear"};

struct FloorConfig {
  bool enabled = true;             // RF; off = one floor calibrated at the start
  int min_support = 300;
  double min_vertical_alignment = 0.7;  // |n . e_y|
  double lower_envelope_fraction = 0.35;
  int ransac_iterations = 200;
  double ransac_inlier_ratio = 0.03;    // inlier distance / camera-to-floor estimate
  // A fit whose camera-to-floor distance is more than this factor away from the last
  // reliable one is a ledge or a step, not the floor ...
  double max_distance_change = 1.5;
  // ... unless this many keyframes in a row agree on such a new distance (a new scale).
  int relock_keyframes = 3;
};

struct CollisionConfig {
  bool pointcloud_enabled = true;
  bool depth_enabled = true;
  // Also count the confident points of the latest previous_steps committed steps
  // (committed_points.h): a wall beside the path is outside a forward camera's view,
  // so the branch's own points rarely show it. 0: only the branch's own points.
  int previous_steps = 15;
  double body_radius = 0.21;   // rho
  double height_low = 0.18;    // eta_low
  double height_high = 1.19;   // eta_high
  // [ours] 0: the paper's eq. 6 (a body cylinder on the floor). > 0: the body climbs
  // steps up to this height (normalised; Quake III's 18 units over the 50-unit eye =
  // 0.36, 0.45 with room for a floor fitted a tread off), riding on a support height
  // followed along the samples (step_support.h); 0 or within [height_low, height_high).
  double step_height = 0;
  // [ours] > 0, with step_height: the body may stand more than height_low over the floor
  // under the eye for at most this many samples in a row; after that the eye has not
  // followed a climb (the world did not lift the camera: a ledge above the player's step),
  // and the disc is counted as the paper counts it over the eye's floor (step_support.h).
  // 0 = off.
  int climb_lag = 0;
  // [ours] What a blocked disc of the stepped body counts (step_support.h): "band", the
  // paper's band over the support (eta_low to eta_high); "above_step", only what rises
  // over the step (step_height to eta_high), so the floor scatter within a step the body
  // would climb is no obstacle mass. Only with step_height > 0. Measured no gain at 60
  // steps on two tuning and two held-out maps (docs/pockets.md, "Floor within a step").
  std::string step_count = "band";
  double min_confidence = 4.0;
  int n_occ = 30;
  int n_occ_consecutive = 2;
  int n_occ_immediate = 300;
  // [ours] > 0: a turn in place is inadmissible while the camera stands where the last
  // committed translation ended with this many points in eq. 6's body cylinder at its
  // last frame (episode.h, docs/inside_brush.md): such a graze can leave the camera
  // inside the brush, and eq. 6 exempts the turns that follow. 0 = off (the paper).
  int turn_contact_points = 0;
  // [ours] > 0: a turn in place is inadmissible while this many committed points stand
  // inside eq. 6's body cylinder at its start (start_occupied, branch_check.h): with
  // exact depth a surface point within the cylinder lies within the player's hull, so
  // the camera stands in contact, maybe inside a brush after a graze eq. 6 did not see
  // (docs/pockets.md). 0 = off (the paper).
  int turn_start_points = 0;
  // [ours] > 0: a translation is inadmissible when N_occ points lie within this many eye
  // heights of the body axis at its last frame (ends_in_contact, branch_check.h). Rho is
  // the hull's inscribed radius (0.30); its corners reach 0.42, so a translation eq. 6
  // passes can end with a corner in a brush, and the turns in place that follow stay
  // there (the hull is axis-aligned: turning does not move it; docs/pockets.md). Only
  // the end pose is held to it, where the agent stands afterwards. 0 = off (the paper).
  double end_clearance = 0;
  // [ours] > 0: a point of the branch or the committed steps counts in eq. 6 only while
  // fewer than this many of the branch's frames saw past it, or no more of them than
  // saw it where it is (free_space_evidence.h, docs/see_through.md): the visual depth
  // scatters points into open space. 0 = off (the paper).
  int see_through_frames = 0;
  // ... a frame saw past a point at depth z when its depth there exceeds (1 + this) z,
  // and saw it when within this share of z.
  double see_through_tolerance = 0.3;
  // [ours] > 0: a committed point counts in eq. 6 only while fewer than this many of the
  // kept committed keyframes' views saw past it, or no more of them than saw it there
  // (committed_points.h; the same evidence and tolerance as see_through_frames, from the
  // committed views instead of the branch's frames). 0 = off (the paper).
  int carve_committed_views = 0;
  double center_fraction = 1.0 / 3.0;
  double d_near = 0.455;
  double s_min_coefficient = 0.085;
  // Clean prefixes [ours] (clean_prefix.h): when no full translation is admissible,
  // the part of each rejected one that stops prefix_margin eye heights short of where
  // its first test fired, its SLAM lost track or N_occ of its points come within
  // prefix_clearance eye heights of the body axis is judged as a candidate of its own,
  // if it advances at least prefix_min_advance eye heights.
  bool prefix_commits = true;
  double prefix_margin = 1.0;
  double prefix_clearance = 0.5;
  double prefix_min_advance = 1.0;
  // [ours] The floor a committed point's normalised height is measured from
  // (committed_points.h): "branch_floor", the branch's first floor (one datum for all);
  // "own_floor", the floor of the point's own keyframe (eq. 5, as for the branch's own
  // points), which cancels a view's error of scale on the floor under it.
  std::string committed_heights = "branch_floor";
};

struct DeadPocketConfig {
  bool enabled = true;
  int rotation_only_steps = 3;
  int checkpoints_kept = 3;
  int max_rewinds = 2;
  int anchor_free_cells = 0;  // [ours] cells within this Chebyshev radius of the anchor stay out of F
  // [ours] Stagnant pockets (rewind_controller.h): 0 = off (the paper).
  int stagnant_steps = 0;     // steps in a row that observe under stagnant_cells new floor cells
  int stagnant_cells = 5;     // coverage-grid cells
  double drop_height = 0.36;  // eye heights: a translation ending this far below its start is a drop (a step is 18 / 50)
  // [ours] A rewind keeps the map and the coverage grid (what the discarded steps
  // observed stays observed) and rewinds only the agent: world, SLAM, trajectory.
  // false = the paper: the map is truncated to the anchor's.
  bool keep_map = false;
  // [ours] A dead pocket, or a stall, that no rewind can follow (no rewind left, or no
  // anchor held: rewinds consumed them all) forgets F, the failed-region memory, so the
  // agent can walk out through the cells earlier rewinds walled off (rewind_controller.h
  // trapped(), docs/pockets.md). false = the paper: F is kept, the agent turns in place,
  // and such a stall ends the episode.
  bool forget_failed_when_trapped = false;
  // [ours] After a rewind F holds no cell of the kept path (the committed frames up to the
  // anchor): a discarded segment that walked back over the way the agent came in would
  // otherwise wall off its way back out (rewind_controller.h, docs/pockets.md).
  // false = the paper: every cell of the discarded segment goes into F.
  bool free_way_back = false;
  // [ours] A rewind whose discarded steps would add no cell to F (their walk stayed in
  // the anchor's cell or in F: a known pocket replayed from the same state, which the
  // same choices would enter again) goes to the held anchor before instead, and so on
  // (rewind_controller.h). false = the paper: the most recent anchor.
  bool reach_past_known_pocket = false;
  // [ours] A translation from a state a rewind went back to, heading within a quarter of
  // jw / lw's turn of a walk that led from that state into the pocket, is inadmissible
  // (rewound_headings.h): a walk that added no cell to F would otherwise be chosen again.
  // false = the paper: F alone bars the way back in.
  bool ban_rewound_headings = false;
  // [ours] A committed translation that ends in the coverage-grid cell it started in
  // counts as a turn for the dead-pocket rule: it resets no count and is no rewind anchor
  // (rewind_controller.h). A short walk that moves no more than a turn does otherwise
  // gives the rewind an anchor from which the same walk is chosen again (docs/pockets.md,
  // the replay loop). false = the paper: every committed translation is one.
  bool walk_in_cell_is_turn = false;
  // [ours] F bars a translation only where it ends (its last camera centre's cell), and
  // the whole-level terms' paths and rays cross F, whose cells are no goal frontier: the
  // cells a discarded segment walked are a line, which otherwise walls off all the space
  // beyond it (docs/pockets.md). false = the paper: a candidate that enters F anywhere
  // is inadmissible.
  bool cross_failed = false;
};

struct MapConfig {
  double min_confidence = 4.0;      // points fused into the map (the collision cut)
  double voxel_eye_heights = 0.05;  // voxel leaf, in camera-to-floor distances
  double octree_eye_heights = 0.1;  // OctoMap resolution, in camera-to-floor distances
  double grid_cell_fraction = 0.5;  // 2D grid cell, as a fraction of a coverage cell
  double max_range_eye_heights = 12; // rays longer than this are cut (far, unreliable depth)
};

// Game-engine exports of a run's map (surface mesh, walkable area, rendered views).
struct ExportConfig {
  double mesh_radius_voxels = 8;      // longest triangle edge, in voxel leaves
  double mesh_mu = 2.5;               // edges at most mu x the local point spacing
  int mesh_max_neighbours = 100;      // neighbours GP3 considers per point
  double mesh_max_surface_angle_deg = 45;  // normals differing more are not joined
  double mesh_min_angle_deg = 10;     // triangle angles kept in [min, max]
  double mesh_max_angle_deg = 120;
  int normal_neighbours = 16;         // points in a normal's PCA neighbourhood
  int mesh_max_points = 400000;       // a larger voxel cloud is meshed at a coarser leaf
  double walkable_cell_fraction = 0.25;  // walkable raster cell, as a fraction of a coverage cell
  double walkable_min_area_m2 = 1.0;  // smaller walkable islands are dropped
  int walkable_close_cells = 2;       // unobserved gaps this many cells wide in the floor count as floor
  int render_width = 640;
  int render_height = 480;
  int orbit_views = 8;
  double orbit_elevation_deg = 40;
  double orbit_fov_deg = 50;
  double render_cut_eye_heights = 1.5;  // renders leave out geometry this far above its floor
  double overview_pixels_per_metre = 16;
  int overview_max_side_px = 4096;      // a larger map is drawn at a smaller scale
};

struct SlamConfig {
  std::string backend = "visual";  // visual | oracle
  int oracle_keyframe_every = 8;   // oracle: a keyframe every N frames
  int cloud_stride_px = 4;         // oracle keyframe clouds keep every N-th pixel per axis
  double oracle_confidence = 10.0; // oracle: constant confidence, above the 4.0 cut
  std::string depth_prior = "none";  // none | learned (depth_prior.h)
  std::string depth_prior_model = "models/depth_prior.onnx";  // relative: to the package folder
  int depth_prior_width = 128;     // the net's input size: OpenCV 4.6 cannot read it from the file
  int depth_prior_height = 96;
  VisualSlamConfig visual;         // the visual backend's tuning (visual_slam_config.h)
};

// Loop closure over the committed keyframes [ours] (docs/loop_closure.md): a new
// committed keyframe is matched against older ones near its predicted pose (ORB, ratio
// test, RANSAC PnP on the old keyframe's depth), and a verified match becomes a
// constraint of the keyframe pose graph, optimised with Ceres (Sim(3) for the visual
// SLAM, SE(3) for the metric oracle). Off: the map is the SLAM's, as before.
struct LoopClosureConfig {
  bool enabled = false;
  int min_age_keyframes = 30;         // candidates are at least this many committed keyframes older
  double radius_eye_heights = 4.0;    // ... with camera centres this close to the new one's predicted centre
  double max_view_angle_deg = 45;     // ... and optical axes this close
  int max_candidates = 3;             // nearest candidates verified per new keyframe
  int features = 500;                 // ORB features per keyframe
  float ratio = 0.8f;                 // Lowe's ratio test on Hamming distances
  float max_distance = 64;            // Hamming distance of an acceptable match, of 256 bits
  int min_matches = 40;               // ratio-test matches with depth on the old keyframe
  int min_inliers = 30;               // RANSAC PnP inliers
  double pnp_threshold_px = 2.0;      // RANSAC PnP inlier distance
  double max_offset_eye_heights = 2.0;  // the match may move the new keyframe this far from its prediction
  double max_rotation_deg = 20;       // ... and turn it this much
  double max_scale_ratio = 1.5;       // ... and rescale it by at most this factor (either way)
  int max_iterations = 50;            // Ceres iterations of one pose graph optimisation
  // [ours] > 0: every keyframe node of a Sim(3) graph also holds its scale s_i to the
  // anchor's eye height, a residual w ln(s_i kappa_i / kappa_0) (kappa_i its camera-to-floor
  // distance in SLAM units): the camera is an eye one known height over its floor, and the
  // visual SLAM's scale drifts 1.1 to 14 times over 60 steps (docs/floor_in_view.md).
  // 0 = off: the graph holds scale only by its edges.
  double eye_height_weight = 0;
  // [ours] ... and a commit whose new keyframes' corrected eye heights are off kappa_0 by
  // more than this share (their median) optimises the graph, as a closure does.
  double eye_height_tolerance = 0.1;
  // [ours] > 0: every keyframe node with a floor fitted on it also holds its roll and
  // pitch to level, a residual w (R_i u_i - g) (u_i its floor normal in camera coordinates,
  // g the anchor floor's): the visual SLAM tilts too, and each keyframe's floor measures
  // by how much (docs/floor_in_view.md). 0 = off.
  double level_weight = 0;
  // [ours] ... and a commit whose new keyframes' corrected floors stand off level by more
  // than this angle (their median, degrees) optimises the graph, as a closure does.
  double level_tolerance_deg = 1.0;
  // [ours] a correction that moves no point of a map keyframe's current copy by more than
  // this (eye heights) keeps that copy: half the map's voxel leaf. 0 = copy every keyframe
  // the graph moved at all.
  double rewrite_tolerance_eye_heights = 0.025;
};

struct Config {
  WorldConfig world;
  RolloutConfig rollout;
  PolicyConfig policy;
  FloorConfig floor;
  CollisionConfig collision;
  DeadPocketConfig dead_pocket;
  MapConfig map;
  SlamConfig slam;
  ExportConfig exports;
  LoopClosureConfig loop_closure;
};

// One configuration as text: a YAML file whose `extends: BASE` (a path relative to the
// file) is merged under it, then overrides (`--set key=value`, a tool's flags, ROS
// parameters) applied on top. Parsing requires every key, so a truncated file is an
// error, never a silent default; an error in an overridden key names the override.
class ConfigDocument {
 public:
  static ConfigDocument load(const std::string& path);
  // `source` names the text in errors; a relative `extends` is found beside it.
  static ConfigDocument fromText(const std::string& yaml_text, const std::string& source);

  // Sets `key` (dotted: "policy.budget_steps") to `value` (YAML scalar text); `origin`
  // ("--budget 20", "parameter /valerant/budget") is what errors about it will name.
  void set(const std::string& key, const std::string& value, const std::string& origin);
  // "key=value", as `--set` takes it.
  void setAssignment(const std::string& assignment, const std::string& origin);

  Config parse() const;
  // The merged, overridden tree as one self-contained YAML file (no `extends`): what a
  // run directory keeps, so the run can be repeated from it alone.
  std::string yaml() const;
  const std::string& source() const { return source_; }

 private:
  YAML::Node root_;
  std::string source_;
  std::map<std::string, std::string> origins_;  // overridden key -> what set it
};

// ConfigDocument::load(path).parse().
Config loadConfig(const std::string& path);
// ConfigDocument::fromText(yaml_text, source).parse().
Config parseConfig(const std::string& yaml_text, const std::string& source);
// config/valerant.yaml of the package folder (package_dir.h; VALERANT_CONFIG overrides).
std::string defaultConfigPath();

}  // namespace valerant
