#include "valerant/config/config.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <utility>

#include "valerant/common/error.h"
#include "valerant/common/joined.h"
#include "valerant/config/package_dir.h"

namespace valerant {
namespace {

// Reads the keys of one YAML mapping into typed fields. Every key must be there (a
// missing one is an error naming it), and anything left over (a typo) is reported
// instead of ignored. Errors name the key's override when one set it, else the file.
class Section {
 public:
  Section(const YAML::Node& node, std::string path, const std::string& source,
          const std::map<std::string, std::string>& origins)
      : node_(node), path_(std::move(path)), source_(source), origins_(origins) {
    if (!node_.IsDefined() || node_.IsNull()) fail(path_, "missing (a config file names every key, or extends a base file that does)");
    if (!node_.IsMap()) fail(path_, "expected a mapping");
  }

  template <typename T>
  void number(const char* key, T& field, T min, T max) {
    const YAML::Node v = take(key);
    T value;
    try {
      if (!v.IsScalar()) throw YAML::Exception(v.Mark(), "not a scalar");
      value = v.as<T>();
    } catch (const YAML::Exception&) {
      fail(name(key), "expected a number, got '" + text(v) + "'");
    }
    if (!(value >= min && value <= max)) {
      std::ostringstream range;
      range << "value " << value << " outside [" << min << ", " << max << "]";
      fail(name(key), range.str());
    }
    field = value;
  }

  // A list of numbers, each in [min, max] (an empty list is allowed).
  template <typename T>
  void numbers(const char* key, std::vector<T>& field, T min, T max) {
    const YAML::Node v = take(key);
    if (!v.IsSequence()) fail(name(key), "expected a list such as [32, 16], got '" + text(v) + "'");
    std::vector<T> values;
    for (const YAML::Node& item : v) {
      T value;
      try {
        if (!item.IsScalar()) throw YAML::Exception(item.Mark(), "not a scalar");
        value = item.as<T>();
      } catch (const YAML::Exception&) {
        fail(name(key), "expected a number in the list, got '" + text(item) + "'");
      }
      if (!(value >= min && value <= max)) {
        std::ostringstream range;
        range << "list value " << value << " outside [" << min << ", " << max << "]";
        fail(name(key), range.str());
      }
      values.push_back(value);
    }
    field = values;
  }

  void boolean(const char* key, bool& field) {
    const YAML::Node v = take(key);
    try {
      if (!v.IsScalar()) throw YAML::Exception(v.Mark(), "not a scalar");
      field = v.as<bool>();
    } catch (const YAML::Exception&) {
      fail(name(key), "expected true or false, got '" + text(v) + "'");
    }
  }

  void choice(const char* key, std::string& field, const std::set<std::string>& allowed) {
    string(key, field);
    if (!allowed.empty() && !allowed.count(field)) {
      fail(name(key), "'" + field + "' is not one of: " + joined(allowed));
    }
  }

  // A list of distinct names, each one of `allowed`.
  void choices(const char* key, std::vector<std::string>& field, const std::set<std::string>& allowed) {
    const YAML::Node v = take(key);
    if (!v.IsSequence()) fail(name(key), "expected a list such as [" + joined(allowed) + "], got '" + text(v) + "'");
    std::vector<std::string> values;
    for (const YAML::Node& item : v) {
      if (!item.IsScalar() || !allowed.count(item.Scalar()))
        fail(name(key), "'" + text(item) + "' is not one of: " + joined(allowed));
      if (std::find(values.begin(), values.end(), item.Scalar()) != values.end())
        fail(name(key), "'" + item.Scalar() + "' is named twice");
      values.push_back(item.Scalar());
    }
    field = values;
  }

  void string(const char* key, std::string& field) {
    const YAML::Node v = take(key);
    if (!v.IsScalar()) fail(name(key), "expected a string");
    field = v.Scalar();
  }

  Section child(const char* key) { return Section(take(key), name(key), source_, origins_); }

  // Every key of the mapping must have been read.
  void finish() const {
    for (const auto& kv : node_) {
      const std::string key = kv.first.as<std::string>();
      if (!used_.count(key)) fail(name(key.c_str()), "unknown key");
    }
  }

  // An error about `key` (its full dotted name), naming the override that set it, else
  // the file: also for the checks across keys once every section is read.
  [[noreturn]] void fail(const std::string& key, const std::string& problem) const {
    const auto origin = origins_.find(key);
    throw InputError(origin == origins_.end() ? source_ : origin->second, key + ": " + problem);
  }

 private:
  // The value under `key`; a missing key is an error. Reads through a const node:
  // yaml-cpp's non-const operator[] would insert the key.
  YAML::Node take(const char* key) {
    used_.insert(key);
    const YAML::Node& map = node_;
    YAML::Node v = map[key];
    if (!v.IsDefined()) fail(name(key), "missing (a config file names every key, or extends a base file that does)");
    return v;
  }
  std::string name(const char* key) const { return path_.empty() ? key : path_ + "." + key; }
  static std::string text(const YAML::Node& v) {
    if (v.IsScalar()) return v.Scalar();
    if (v.IsNull()) return "";  // "key:" with no value in a file, or --set key=
    return v.IsSequence() ? "<sequence>" : "<mapping>";
  }

  YAML::Node node_;
  std::string path_;
  const std::string& source_;
  const std::map<std::string, std::string>& origins_;
  std::set<std::string> used_;
};

void readWorld(Section s, WorldConfig& w) {
  s.choice("backend", w.backend, {"quake3", "bag", "learned"});
  s.string("map", w.map);
  s.number("spawn", w.spawn, 0, 1000);
  s.number("width", w.width, 32, 4096);
  s.number("height", w.height, 32, 4096);
  s.number("fov_x_deg", w.fov_x_deg, 10.0, 170.0);
  s.number("d_fwd_units", w.d_fwd_units, 1.0, 10000.0);
  s.number("eye_height_units", w.eye_height_units, 1.0, 1000.0);
  s.number("near_plane_units", w.near_plane_units, 0.01, 100.0);
  s.number("far_plane_units", w.far_plane_units, 100.0, 1e6);
  s.number("patch_level", w.patch_level, 1, 64);
  s.number("max_drop_units", w.max_drop_units, 0.0, 1e5);
  s.number("seed", w.seed, 0u, 0xffffffffu);
  Section d = s.child("degradation");
  d.number("noise_sigma", w.degradation.noise_sigma, 0.0, 128.0);
  d.number("blur_sigma", w.degradation.blur_sigma, 0.0, 20.0);
  d.number("exposure_flicker", w.degradation.exposure_flicker, 0.0, 0.9);
  d.number("jitter_px", w.degradation.jitter_px, 0.0, 50.0);
  d.finish();
  Section l = s.child("learned");
  l.string("model", w.learned.model);
  l.number("width", w.learned.width, 8, 4096);
  l.number("height", w.learned.height, 8, 4096);
  l.number("context_frames", w.learned.context_frames, 1, 64);
  l.choice("warp", w.learned.warp, {"last_frame", "rotation_anchor", "pose_anchor"});
  l.string("depth_prior_model", w.learned.depth_prior_model);
  l.finish();
  s.finish();
}

void readRollout(Section s, RolloutConfig& r) {
  s.number("context_frames", r.context_frames, 1, 1000);
  s.number("horizon_frames", r.horizon_frames, 1, 10000);
  s.number("turn_forward_frames", r.turn_forward_frames, 0, 10000);
  s.number("turn_forward_deg", r.turn_forward_deg, 0.0, 360.0);
  s.number("rotate_deg", r.rotate_deg, 0.0, 360.0);
  s.number("flow_steps", r.flow_steps, 1, 1000);
  s.number("cfg_scale", r.cfg_scale, 0.0, 100.0);
  s.finish();
}

void readPolicy(Section s, PolicyConfig& p) {
  s.choice("kind", p.kind, {"valerant", "random", "forward", "frontier"});
  s.number("lambda_cov", p.lambda_cov, 0.0, 1e6);
  s.number("lambda_prog", p.lambda_prog, 0.0, 1e6);
  s.number("frontier_weight", p.frontier_weight, 0.0, 1e6);
  s.number("grid_cells", p.grid_cells, 8, 4096);
  s.number("cells_per_d_fwd", p.cells_per_d_fwd, 1, 1024);
  s.number("budget_steps", p.budget_steps, 1, 100000);
  s.number("step_cap_factor", p.step_cap_factor, 1, 1000);
  s.number("max_progress", p.max_progress, 0.0, 1e6);
  s.number("goal_weight", p.goal_weight, 0.0, 1e6);
  s.number("obstacle_min_points", p.obstacle_min_points, 1, 1000000);
  s.number("max_cell_rise", p.max_cell_rise, 0.0, 100.0);
  s.number("surface_carving_ratio", p.surface_carving_ratio, 0.0, 1e6);
  s.numbers("short_translation_frames", p.short_translation_frames, 1, 10000);
  s.numbers("short_turn_frames", p.short_turn_frames, 1, 10000);
  s.boolean("open_turn", p.open_turn);
  s.boolean("goal_move", p.goal_move);
  s.number("opening_weight", p.opening_weight, 0.0, 1e6);
  s.boolean("no_turn_back", p.no_turn_back);
  s.choices("yielding_objections", p.yielding_objections, kYieldableObjections);
  s.finish();
}

void readFloor(Section s, FloorConfig& f) {
  s.boolean("enabled", f.enabled);
  s.number("min_support", f.min_support, 3, 10000000);
  s.number("min_vertical_alignment", f.min_vertical_alignment, 0.0, 1.0);
  s.number("lower_envelope_fraction", f.lower_envelope_fraction, 0.01, 1.0);
  s.number("ransac_iterations", f.ransac_iterations, 1, 100000);
  s.number("ransac_inlier_ratio", f.ransac_inlier_ratio, 1e-6, 1.0);
  s.number("max_distance_change", f.max_distance_change, 1.0, 1e6);
  s.number("relock_keyframes", f.relock_keyframes, 1, 100000);
  s.finish();
}

void readCollision(Section s, CollisionConfig& c) {
  s.boolean("pointcloud_enabled", c.pointcloud_enabled);
  s.boolean("depth_enabled", c.depth_enabled);
  s.number("previous_steps", c.previous_steps, 0, 100000);
  s.number("body_radius", c.body_radius, 0.0, 10.0);
  s.number("height_low", c.height_low, -10.0, 10.0);
  s.number("height_high", c.height_high, -10.0, 10.0);
  s.number("step_height", c.step_height, 0.0, 10.0);
  s.number("climb_lag", c.climb_lag, 0, 100000);
  s.choice("step_count", c.step_count, {"band", "above_step"});
  s.number("min_confidence", c.min_confidence, 0.0, 1e6);
  s.number("n_occ", c.n_occ, 1, 10000000);
  s.number("n_occ_consecutive", c.n_occ_consecutive, 1, 1000);
  s.number("n_occ_immediate", c.n_occ_immediate, 1, 10000000);
  s.number("turn_contact_points", c.turn_contact_points, 0, 10000000);
  s.number("turn_start_points", c.turn_start_points, 0, 10000000);
  s.number("end_clearance", c.end_clearance, 0.0, 100.0);
  s.number("see_through_frames", c.see_through_frames, 0, 100000);
  s.number("see_through_tolerance", c.see_through_tolerance, 0.01, 10.0);
  s.number("carve_committed_views", c.carve_committed_views, 0, 100000);
  s.number("center_fraction", c.center_fraction, 0.01, 1.0);
  s.number("d_near", c.d_near, 0.0, 100.0);
  s.number("s_min_coefficient", c.s_min_coefficient, 0.0, 10.0);
  s.boolean("prefix_commits", c.prefix_commits);
  s.number("prefix_margin", c.prefix_margin, 0.0, 100.0);
  s.number("prefix_clearance", c.prefix_clearance, 0.0, 100.0);
  s.number("prefix_min_advance", c.prefix_min_advance, 0.0, 100.0);
  s.choice("committed_heights", c.committed_heights, {"branch_floor", "own_floor"});
  s.finish();
}

// slam.visual: the ranges keep each value where its use makes sense (a RANSAC
// confidence below 1, at least the points a minimal solver needs, windows of a pixel or
// more); pairs that bound each other are checked in parse().
void readVisualSlam(Section s, VisualSlamConfig& v) {
  Section t = s.child("tracker");
  t.number("max_features", v.tracker.max_features, 1, 100000);
  t.number("redetect_below", v.tracker.redetect_below, 0, 100000);
  t.number("corner_quality", v.tracker.corner_quality, 1e-6, 1.0);
  t.number("min_distance_px", v.tracker.min_distance_px, 1, 1000);
  t.number("window_px", v.tracker.window_px, 3, 101);
  t.number("pyramid_levels", v.tracker.pyramid_levels, 0, 10);
  t.number("iterations", v.tracker.iterations, 1, 1000);
  t.number("max_forward_backward_px", v.tracker.max_forward_backward_px, 0.0, 100.0);
  t.finish();
  Section tv = s.child("two_view");
  tv.number("ransac_threshold_px", v.two_view.ransac_threshold_px, 1e-3, 100.0);
  tv.number("min_points", v.two_view.min_points, 5, 100000);
  tv.number("min_point_parallax_deg", v.two_view.min_point_parallax_deg, 0.0, 90.0);
  tv.number("min_median_parallax_deg", v.two_view.min_median_parallax_deg, 0.0, 90.0);
  tv.number("max_reprojection_px", v.two_view.max_reprojection_px, 1e-3, 100.0);
  tv.number("rotation_parallax_px", v.two_view.rotation_parallax_px, 0.0, 1000.0);
  tv.finish();
  Section p = s.child("pnp");
  p.number("min_inliers", v.pnp.min_inliers, 4, 100000);
  p.number("threshold_px", v.pnp.threshold_px, 1e-3, 100.0);
  p.number("iterations", v.pnp.iterations, 1, 100000);
  p.number("confidence", v.pnp.confidence, 0.01, 0.999999);
  p.finish();
  Section k = s.child("keyframe");
  k.number("max_interval", v.keyframe.max_interval, 1, 10000);
  k.number("min_tracked_ratio", v.keyframe.min_tracked_ratio, 0.0, 1.0);
  k.number("min_baseline_ratio", v.keyframe.min_baseline_ratio, 0.0, 10.0);
  k.number("rotation_only_ratio", v.keyframe.rotation_only_ratio, 0.0, 10.0);
  k.number("min_tracks", v.keyframe.min_tracks, 5, 100000);
  k.finish();
  Section b = s.child("bundle_adjustment");
  b.number("window", v.bundle_adjustment.window, 1, 1000);
  b.number("huber_px", v.bundle_adjustment.huber_px, 1e-3, 100.0);
  b.number("max_iterations", v.bundle_adjustment.max_iterations, 0, 1000);
  b.number("max_error_px", v.bundle_adjustment.max_error_px, 1e-3, 1000.0);
  b.finish();
  Section sw = s.child("sweep");
  sw.number("downsample", v.sweep.downsample, 1, 16);
  sw.number("normalise_window_px", v.sweep.normalise_window_px, 1, 101);
  sw.number("contrast_floor", v.sweep.contrast_floor, 0.0, 255.0);
  sw.number("max_planes", v.sweep.max_planes, 4, 1024);
  sw.number("min_planes", v.sweep.min_planes, 4, 1024);
  sw.number("min_plane", v.sweep.min_plane, 0.0, 1024.0);
  sw.number("plane_step_px", v.sweep.plane_step_px, 1e-3, 100.0);
  sw.number("sources", v.sweep.sources, 1, 16);
  sw.number("window_px", v.sweep.window_px, 1, 101);
  sw.number("truncation", v.sweep.truncation, 1e-3, 100.0);
  sw.number("noise_level", v.sweep.noise_level, 0.0, 100.0);
  sw.number("min_baseline_ratio", v.sweep.min_baseline_ratio, 0.0, 10.0);
  sw.number("max_baseline_ratio", v.sweep.max_baseline_ratio, 0.0, 10.0);
  sw.number("max_view_angle_deg", v.sweep.max_view_angle_deg, 0.0, 180.0);
  sw.number("min_shared_ratio", v.sweep.min_shared_ratio, 0.0, 1.0);
  sw.number("min_shared_points", v.sweep.min_shared_points, 0, 100000);
  sw.number("near_fraction", v.sweep.near_fraction, 1e-3, 1.0);
  sw.number("confidence_gain", v.sweep.confidence_gain, 0.0, 1e3);
  sw.number("max_confidence", v.sweep.max_confidence, 0.0, 1e6);
  sw.boolean("simd", v.sweep.simd);
  sw.finish();
  Section r = s.child("relocalizer");
  r.number("patch_px", v.relocalizer.patch_px, 3, 255);
  r.number("max_distance", v.relocalizer.max_distance, 0.f, 256.f);
  r.number("ratio", v.relocalizer.ratio, 0.01f, 1.f);
  r.number("keyframes", v.relocalizer.keyframes, 1, 10000);
  r.number("min_inliers", v.relocalizer.min_inliers, 4, 100000);
  r.finish();
  Section d = s.child("prior");
  d.number("confidence_gain", v.prior.fusion.confidence_gain, 0.0, 1e3);
  d.number("max_confidence", v.prior.fusion.max_confidence, 0.0, 1e6);
  d.number("max_depth_m", v.prior.fusion.max_depth_m, 1e-3, 1e6);
  d.number("min_confidence", v.prior.fusion.min_confidence, 0.0, 1e6);
  d.number("min_scale_pixels", v.prior.fusion.min_scale_pixels, 1, 100000000);
  d.number("view_angle_deg", v.prior.view_angle_deg, 0.0, 180.0);
  d.finish();
  s.number("seed", v.seed, uint64_t{0}, std::numeric_limits<uint64_t>::max());
  s.finish();
}

// A value that must not exceed another of the same file.
void requireAtMost(const std::string& source, const char* low_key, double low, const char* high_key, double high) {
  if (low > high) throw InputError(source, std::string(low_key) + ": must not exceed " + high_key);
}

void readDeadPocket(Section s, DeadPocketConfig& d) {
  s.boolean("enabled", d.enabled);
  s.number("rotation_only_steps", d.rotation_only_steps, 1, 1000);
  s.number("checkpoints_kept", d.checkpoints_kept, 1, 1000);
  s.number("max_rewinds", d.max_rewinds, 0, 1000);
  s.number("anchor_free_cells", d.anchor_free_cells, 0, 64);
  s.number("stagnant_steps", d.stagnant_steps, 0, 100000);
  s.number("stagnant_cells", d.stagnant_cells, 1, 100000);
  s.number("drop_height", d.drop_height, 0.0, 100.0);
  s.boolean("keep_map", d.keep_map);
  s.boolean("forget_failed_when_trapped", d.forget_failed_when_trapped);
  s.boolean("free_way_back", d.free_way_back);
  s.boolean("reach_past_known_pocket", d.reach_past_known_pocket);
  s.boolean("ban_rewound_headings", d.ban_rewound_headings);
  s.boolean("walk_in_cell_is_turn", d.walk_in_cell_is_turn);
  s.boolean("cross_failed", d.cross_failed);
  s.finish();
}

void readLoopClosure(Section s, LoopClosureConfig& l) {
  s.boolean("enabled", l.enabled);
  s.number("min_age_keyframes", l.min_age_keyframes, 1, 1000000);
  s.number("radius_eye_heights", l.radius_eye_heights, 0.0, 1e4);
  s.number("max_view_angle_deg", l.max_view_angle_deg, 0.0, 180.0);
  s.number("max_candidates", l.max_candidates, 0, 1000);
  s.number("features", l.features, 10, 100000);
  s.number("ratio", l.ratio, 0.01f, 1.f);
  s.number("max_distance", l.max_distance, 0.f, 256.f);
  s.number("min_matches", l.min_matches, 4, 100000);
  s.number("min_inliers", l.min_inliers, 4, 100000);
  s.number("pnp_threshold_px", l.pnp_threshold_px, 1e-3, 100.0);
  s.number("max_offset_eye_heights", l.max_offset_eye_heights, 0.0, 1e4);
  s.number("max_rotation_deg", l.max_rotation_deg, 0.0, 180.0);
  s.number("max_scale_ratio", l.max_scale_ratio, 1.0, 100.0);
  s.number("max_iterations", l.max_iterations, 1, 10000);
  s.number("eye_height_weight", l.eye_height_weight, 0.0, 1e6);
  s.number("eye_height_tolerance", l.eye_height_tolerance, 0.0, 10.0);
  s.number("level_weight", l.level_weight, 0.0, 1e6);
  s.number("level_tolerance_deg", l.level_tolerance_deg, 0.0, 90.0);
  s.number("rewrite_tolerance_eye_heights", l.rewrite_tolerance_eye_heights, 0.0, 1.0);
  s.finish();
}

}  // namespace

namespace {

constexpr int kMaxExtendsDepth = 8;

YAML::Node loadYaml(const std::string& text, const std::string& source) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(source, std::string("invalid YAML: ") + e.what());
  }
}

std::string readText(const std::string& path) {
  // A folder opens as an empty stream: it would read as an empty file.
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored)) throw InputError(path, "is a folder, not a config file");
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot read config file");
  std::stringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(path, "cannot read config file");
  return text.str();
}

// `over` laid on `base`: mappings merge key by key, anything else replaces.
YAML::Node merged(const YAML::Node& base, const YAML::Node& over) {
  if (!base.IsMap() || !over.IsMap()) return YAML::Clone(over);
  YAML::Node out = YAML::Clone(base);
  for (const auto& kv : over) {
    const std::string key = kv.first.as<std::string>();
    const YAML::Node& base_const = base;
    out[key] = base_const[key].IsDefined() ? merged(base_const[key], kv.second) : YAML::Clone(kv.second);
  }
  return out;
}

// The tree of `text` with its `extends` chain resolved; `seen` guards against a cycle.
YAML::Node resolvedTree(const std::string& text, const std::string& source, std::vector<std::string>& seen) {
  YAML::Node root = loadYaml(text, source);
  if (!root || root.IsNull())
    throw InputError(source, "empty (a config file names every key, or extends a base file that does)");
  if (!root.IsMap()) throw InputError(source, "expected a mapping at the top");
  const YAML::Node& const_root = root;
  const YAML::Node extends = const_root["extends"];
  if (!extends.IsDefined()) return root;
  if (!extends.IsScalar() || extends.Scalar().empty())
    throw InputError(source, "extends: expected the path of a base config file");
  std::filesystem::path base = extends.Scalar();
  if (base.is_relative()) base = std::filesystem::path(source).parent_path() / base;
  const std::string base_path = base.lexically_normal().string();
  if (std::find(seen.begin(), seen.end(), base_path) != seen.end() || seen.size() > kMaxExtendsDepth)
    throw InputError(source, "extends: " + base_path + " extends this file again (a cycle)");
  seen.push_back(base_path);
  YAML::Node base_tree = resolvedTree(readText(base_path), base_path, seen);
  root.remove("extends");
  return merged(base_tree, root);
}

}  // namespace

ConfigDocument ConfigDocument::load(const std::string& path) { return fromText(readText(path), path); }

ConfigDocument ConfigDocument::fromText(const std::string& yaml_text, const std::string& source) {
  ConfigDocument doc;
  std::vector<std::string> seen = {std::filesystem::path(source).lexically_normal().string()};
  doc.root_ = resolvedTree(yaml_text, source, seen);
  doc.source_ = source;
  return doc;
}

void ConfigDocument::set(const std::string& key, const std::string& value, const std::string& origin) {
  if (key.empty() || key.front() == '.' || key.back() == '.' || key.find("..") != std::string::npos)
    throw InputError(origin, "'" + key + "' is not a key (expected section.key, e.g. policy.budget_steps)");
  std::vector<std::string> parts;
  std::stringstream in(key);
  for (std::string part; std::getline(in, part, '.');) parts.push_back(part);
  // Walk down through mappings, making any missing level: the strict parse then
  // reports a key that does not exist, naming `origin`.
  std::vector<YAML::Node> chain = {root_};
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node next = chain.back()[parts[i]];
    if (next.IsDefined() && !next.IsNull() && !next.IsMap())
      throw InputError(origin, key + ": " + parts[i] + " is a value, not a section");
    chain.push_back(next);
  }
  YAML::Node parsed = loadYaml(value, origin);
  chain.back()[parts.back()] = parsed.IsDefined() ? parsed : YAML::Node(YAML::NodeType::Null);
  origins_[key] = origin;
}

void ConfigDocument::setAssignment(const std::string& assignment, const std::string& origin) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos) throw InputError(origin, "expected key=value (e.g. policy.budget_steps=30)");
  set(assignment.substr(0, eq), assignment.substr(eq + 1), origin);
}

std::string ConfigDocument::yaml() const {
  YAML::Emitter out;
  out << root_;
  return std::string("# valerant configuration, resolved (base files merged, overrides applied) from ") + source_ +
         "\n" + out.c_str() + "\n";
}

Config ConfigDocument::parse() const {
  Config c;
  const YAML::Node& root = root_;
  const std::string& source = source_;
  Section top(root, "", source, origins_);
  readWorld(top.child("world"), c.world);
  readRollout(top.child("rollout"), c.rollout);
  readPolicy(top.child("policy"), c.policy);
  readFloor(top.child("floor"), c.floor);
  readCollision(top.child("collision"), c.collision);
  readDeadPocket(top.child("dead_pocket"), c.dead_pocket);
  Section map = top.child("map");
  map.number("min_confidence", c.map.min_confidence, 0.0, 1e6);
  map.number("voxel_eye_heights", c.map.voxel_eye_heights, 1e-4, 10.0);
  map.number("octree_eye_heights", c.map.octree_eye_heights, 1e-4, 10.0);
  map.number("grid_cell_fraction", c.map.grid_cell_fraction, 0.01, 10.0);
  map.number("max_range_eye_heights", c.map.max_range_eye_heights, 0.1, 1e4);
  map.finish();
  Section slam = top.child("slam");
  slam.choice("backend", c.slam.backend, {"visual", "oracle"});
  slam.number("oracle_keyframe_every", c.slam.oracle_keyframe_every, 1, 10000);
  slam.number("cloud_stride_px", c.slam.cloud_stride_px, 1, 64);
  slam.number("oracle_confidence", c.slam.oracle_confidence, 0.0, 1e6);
  slam.choice("depth_prior", c.slam.depth_prior, {"none", "learned"});
  slam.string("depth_prior_model", c.slam.depth_prior_model);
  slam.number("depth_prior_width", c.slam.depth_prior_width, 8, 4096);
  slam.number("depth_prior_height", c.slam.depth_prior_height, 8, 4096);
  readVisualSlam(slam.child("visual"), c.slam.visual);
  slam.finish();
  Section exports = top.child("exports");
  exports.number("mesh_radius_voxels", c.exports.mesh_radius_voxels, 1.0, 100.0);
  exports.number("mesh_mu", c.exports.mesh_mu, 1.0, 100.0);
  exports.number("mesh_max_neighbours", c.exports.mesh_max_neighbours, 3, 10000);
  exports.number("mesh_max_surface_angle_deg", c.exports.mesh_max_surface_angle_deg, 0.0, 180.0);
  exports.number("mesh_min_angle_deg", c.exports.mesh_min_angle_deg, 0.0, 60.0);
  exports.number("mesh_max_angle_deg", c.exports.mesh_max_angle_deg, 60.0, 180.0);
  exports.number("normal_neighbours", c.exports.normal_neighbours, 3, 10000);
  exports.number("mesh_max_points", c.exports.mesh_max_points, 1000, 100000000);
  exports.number("walkable_cell_fraction", c.exports.walkable_cell_fraction, 0.01, 10.0);
  exports.number("walkable_min_area_m2", c.exports.walkable_min_area_m2, 0.0, 1e6);
  exports.number("walkable_close_cells", c.exports.walkable_close_cells, 0, 100);
  exports.number("render_width", c.exports.render_width, 16, 8192);
  exports.number("render_height", c.exports.render_height, 16, 8192);
  exports.number("orbit_views", c.exports.orbit_views, 1, 360);
  exports.number("orbit_elevation_deg", c.exports.orbit_elevation_deg, 0.0, 90.0);
  exports.number("orbit_fov_deg", c.exports.orbit_fov_deg, 1.0, 170.0);
  exports.number("render_cut_eye_heights", c.exports.render_cut_eye_heights, 0.0, 1e3);
  exports.number("overview_pixels_per_metre", c.exports.overview_pixels_per_metre, 0.1, 1000.0);
  exports.number("overview_max_side_px", c.exports.overview_max_side_px, 16, 8192);
  exports.finish();
  readLoopClosure(top.child("loop_closure"), c.loop_closure);
  top.finish();
  if (c.collision.height_low >= c.collision.height_high)
    throw InputError(source, "collision.height_low: must be below collision.height_high");
  // A step below eta_low would make the stepped cylinder block on points the paper's
  // ignores; one at eta_high would leave it nothing to count.
  if (const double s = c.collision.step_height; s != 0 && (s < c.collision.height_low || s >= c.collision.height_high)) {
    std::ostringstream problem;
    problem << s << " is neither 0 (the paper's test) nor within [collision.height_low, collision.height_high) = ["
            << c.collision.height_low << ", " << c.collision.height_high << ")";
    top.fail("collision.step_height", problem.str());
  }
  if (c.collision.climb_lag > 0 && c.collision.step_height == 0)
    top.fail("collision.climb_lag", "bounds the stepped body's climbs, so it needs collision.step_height > 0");
  if (c.collision.step_count != "band" && c.collision.step_height == 0)
    top.fail("collision.step_count", "chooses what the stepped body counts, so it needs collision.step_height > 0");
  // Short translations and turns are prefixes of uw / jq: shorter than their horizon.
  for (const auto& [key, frames] : {std::pair{"policy.short_translation_frames", &c.policy.short_translation_frames},
                                    std::pair{"policy.short_turn_frames", &c.policy.short_turn_frames}})
    for (const int f : *frames)
      if (f >= c.rollout.horizon_frames)
        top.fail(key, std::to_string(f) + " frames is not shorter than rollout.horizon_frames (" +
                          std::to_string(c.rollout.horizon_frames) + ")");
  const VisualSlamConfig& v = c.slam.visual;
  requireAtMost(source, "slam.visual.tracker.redetect_below", v.tracker.redetect_below, "slam.visual.tracker.max_features",
                v.tracker.max_features);
  requireAtMost(source, "slam.visual.sweep.min_planes", v.sweep.min_planes, "slam.visual.sweep.max_planes",
                v.sweep.max_planes);
  requireAtMost(source, "slam.visual.sweep.min_baseline_ratio", v.sweep.min_baseline_ratio,
                "slam.visual.sweep.max_baseline_ratio", v.sweep.max_baseline_ratio);
  requireAtMost(source, "loop_closure.min_inliers", c.loop_closure.min_inliers, "loop_closure.min_matches",
                c.loop_closure.min_matches);
  return c;
}

Config loadConfig(const std::string& path) { return ConfigDocument::load(path).parse(); }

Config parseConfig(const std::string& yaml_text, const std::string& source) {
  return ConfigDocument::fromText(yaml_text, source).parse();
}

std::string defaultConfigPath() {
  if (const char* env = std::getenv("VALERANT_CONFIG"); env && *env) return env;
  return packageFilePath("config/valerant.yaml");
}

}  // namespace valerant
