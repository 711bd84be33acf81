// Config loading: the shipped file matches the paper, and every kind of mistake is
// reported with the file and the key.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "valerant/common/error.h"
#include "valerant/config/config.h"

using namespace valerant;

namespace {

const std::string kShipped = std::string(VALERANT_SOURCE_DIR) + "/config/valerant.yaml";

// The shipped file with `yaml` laid over it, as a user's file extending it would be.
std::string overShipped(const std::string& yaml) { return "extends: " + kShipped + "\n" + yaml; }

std::string errorOf(const std::string& yaml) {
  try {
    parseConfig(overShipped(yaml), "test.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A scratch folder for config files that extend each other.
std::filesystem::path scratchFolder(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("valerant_test_config_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

void writeText(const std::filesystem::path& path, const std::string& text) { std::ofstream(path) << text; }

}  // namespace

TEST(Config, ShippedFileHasThePapersValues) {
  const Config c = loadConfig(std::string(VALERANT_SOURCE_DIR) + "/config/valerant.yaml");
  EXPECT_EQ(c.rollout.context_frames, 16);
  EXPECT_EQ(c.rollout.horizon_frames, 57);
  EXPECT_EQ(c.rollout.turn_forward_frames, 40);
  EXPECT_EQ(c.rollout.flow_steps, 3);
  EXPECT_DOUBLE_EQ(c.rollout.cfg_scale, 5.0);
  EXPECT_DOUBLE_EQ(c.policy.lambda_cov, 1.0);
  EXPECT_DOUBLE_EQ(c.policy.lambda_prog, 5.0);
  EXPECT_DOUBLE_EQ(c.policy.frontier_weight, 0.5);
  EXPECT_EQ(c.policy.grid_cells, 512);  // [ours]: the paper's 128 x 128 is too small for whole levels
  EXPECT_EQ(c.policy.cells_per_d_fwd, 8);
  EXPECT_EQ(c.policy.budget_steps, 15);
  EXPECT_EQ(c.floor.min_support, 300);
  EXPECT_DOUBLE_EQ(c.floor.min_vertical_alignment, 0.7);
  EXPECT_DOUBLE_EQ(c.collision.body_radius, 0.30);
  EXPECT_DOUBLE_EQ(c.collision.height_low, 0.18);
  EXPECT_DOUBLE_EQ(c.collision.height_high, 1.19);
  EXPECT_DOUBLE_EQ(c.collision.step_height, 0.0);  // [ours], off: the paper's cylinder
  EXPECT_EQ(c.collision.climb_lag, 0);               // [ours], off
  EXPECT_EQ(c.collision.step_count, "band");         // [ours]: the paper's band (only read with step_height)
  EXPECT_DOUBLE_EQ(c.collision.min_confidence, 4.0);
  EXPECT_EQ(c.collision.n_occ, 30);
  EXPECT_EQ(c.collision.n_occ_consecutive, 2);
  EXPECT_EQ(c.collision.n_occ_immediate, 300);
  EXPECT_EQ(c.collision.turn_contact_points, 0);  // [ours], off: the paper exempts every turn
  EXPECT_EQ(c.collision.turn_start_points, 0);    // [ours], off
  EXPECT_EQ(c.collision.end_clearance, 0.0);      // [ours], off
  EXPECT_EQ(c.collision.see_through_frames, 0);   // [ours], off
  EXPECT_DOUBLE_EQ(c.collision.see_through_tolerance, 0.3);
  EXPECT_EQ(c.collision.carve_committed_views, 0);  // [ours], off
  EXPECT_NEAR(c.collision.center_fraction, 1.0 / 3.0, 1e-9);
  EXPECT_DOUBLE_EQ(c.collision.d_near, 0.455);
  EXPECT_DOUBLE_EQ(c.collision.s_min_coefficient, 0.085);
  EXPECT_EQ(c.dead_pocket.rotation_only_steps, 3);
  EXPECT_EQ(c.dead_pocket.checkpoints_kept, 3);
  EXPECT_EQ(c.dead_pocket.max_rewinds, 2);
  EXPECT_EQ(c.dead_pocket.anchor_free_cells, 0);
  EXPECT_EQ(c.dead_pocket.stagnant_steps, 0);  // [ours], off: only the paper's rotations declare a dead pocket
  EXPECT_EQ(c.dead_pocket.stagnant_cells, 5);
  EXPECT_DOUBLE_EQ(c.dead_pocket.drop_height, 0.36);
  EXPECT_FALSE(c.dead_pocket.keep_map);  // [ours], off: a rewind truncates the map (the paper)
  EXPECT_EQ(c.world.width, 320);
  EXPECT_EQ(c.world.height, 240);
  EXPECT_DOUBLE_EQ(c.world.d_fwd_units, 256);
  EXPECT_EQ(c.slam.backend, "visual");
}

TEST(Config, ShippedVisualSlamValuesAreTheBuiltInOnes) {
  // slam.visual moved out of the code into the file: every value must be the one the
  // SLAM was tuned with (the structs' defaults), exactly, so no decision changes.
  const VisualSlamConfig shipped = loadConfig(kShipped).slam.visual;
  const VisualSlamConfig built_in;
  EXPECT_EQ(shipped.tracker.max_features, built_in.tracker.max_features);
  EXPECT_EQ(shipped.tracker.redetect_below, built_in.tracker.redetect_below);
  EXPECT_EQ(shipped.tracker.corner_quality, built_in.tracker.corner_quality);
  EXPECT_EQ(shipped.tracker.min_distance_px, built_in.tracker.min_distance_px);
  EXPECT_EQ(shipped.tracker.window_px, built_in.tracker.window_px);
  EXPECT_EQ(shipped.tracker.pyramid_levels, built_in.tracker.pyramid_levels);
  EXPECT_EQ(shipped.tracker.iterations, built_in.tracker.iterations);
  EXPECT_EQ(shipped.tracker.max_forward_backward_px, built_in.tracker.max_forward_backward_px);
  EXPECT_EQ(shipped.two_view.ransac_threshold_px, built_in.two_view.ransac_threshold_px);
  EXPECT_EQ(shipped.two_view.min_points, built_in.two_view.min_points);
  EXPECT_EQ(shipped.two_view.min_point_parallax_deg, built_in.two_view.min_point_parallax_deg);
  EXPECT_EQ(shipped.two_view.min_median_parallax_deg, built_in.two_view.min_median_parallax_deg);
  EXPECT_EQ(shipped.two_view.max_reprojection_px, built_in.two_view.max_reprojection_px);
  EXPECT_EQ(shipped.two_view.rotation_parallax_px, built_in.two_view.rotation_parallax_px);
  EXPECT_EQ(shipped.pnp.min_inliers, built_in.pnp.min_inliers);
  EXPECT_EQ(shipped.pnp.threshold_px, built_in.pnp.threshold_px);
  EXPECT_EQ(shipped.pnp.iterations, built_in.pnp.iterations);
  EXPECT_EQ(shipped.pnp.confidence, built_in.pnp.confidence);
  EXPECT_EQ(shipped.keyframe.max_interval, built_in.keyframe.max_interval);
  EXPECT_EQ(shipped.keyframe.min_tracked_ratio, built_in.keyframe.min_tracked_ratio);
  EXPECT_EQ(shipped.keyframe.min_baseline_ratio, built_in.keyframe.min_baseline_ratio);
  EXPECT_EQ(shipped.keyframe.rotation_only_ratio, built_in.keyframe.rotation_only_ratio);
  EXPECT_EQ(shipped.keyframe.min_tracks, built_in.keyframe.min_tracks);
  EXPECT_EQ(shipped.bundle_adjustment.window, built_in.bundle_adjustment.window);
  EXPECT_EQ(shipped.bundle_adjustment.huber_px, built_in.bundle_adjustment.huber_px);
  EXPECT_EQ(shipped.bundle_adjustment.max_iterations, built_in.bundle_adjustment.max_iterations);
  EXPECT_EQ(shipped.bundle_adjustment.max_error_px, built_in.bundle_adjustment.max_error_px);
  EXPECT_EQ(shipped.sweep.downsample, built_in.sweep.downsample);
  EXPECT_EQ(shipped.sweep.normalise_window_px, built_in.sweep.normalise_window_px);
  EXPECT_EQ(shipped.sweep.contrast_floor, built_in.sweep.contrast_floor);
  EXPECT_EQ(shipped.sweep.max_planes, built_in.sweep.max_planes);
  EXPECT_EQ(shipped.sweep.min_planes, built_in.sweep.min_planes);
  EXPECT_EQ(shipped.sweep.min_plane, built_in.sweep.min_plane);
  EXPECT_EQ(shipped.sweep.plane_step_px, built_in.sweep.plane_step_px);
  EXPECT_EQ(shipped.sweep.sources, built_in.sweep.sources);
  EXPECT_EQ(shipped.sweep.window_px, built_in.sweep.window_px);
  EXPECT_EQ(shipped.sweep.truncation, built_in.sweep.truncation);
  EXPECT_EQ(shipped.sweep.noise_level, built_in.sweep.noise_level);
  EXPECT_EQ(shipped.sweep.min_baseline_ratio, built_in.sweep.min_baseline_ratio);
  EXPECT_EQ(shipped.sweep.max_baseline_ratio, built_in.sweep.max_baseline_ratio);
  EXPECT_EQ(shipped.sweep.max_view_angle_deg, built_in.sweep.max_view_angle_deg);
  EXPECT_EQ(shipped.sweep.min_shared_ratio, built_in.sweep.min_shared_ratio);
  EXPECT_EQ(shipped.sweep.min_shared_points, built_in.sweep.min_shared_points);
  EXPECT_EQ(shipped.sweep.near_fraction, built_in.sweep.near_fraction);
  EXPECT_EQ(shipped.sweep.confidence_gain, built_in.sweep.confidence_gain);
  EXPECT_EQ(shipped.sweep.max_confidence, built_in.sweep.max_confidence);
  EXPECT_EQ(shipped.sweep.simd, built_in.sweep.simd);
  EXPECT_EQ(shipped.relocalizer.patch_px, built_in.relocalizer.patch_px);
  EXPECT_EQ(shipped.relocalizer.max_distance, built_in.relocalizer.max_distance);
  EXPECT_EQ(shipped.relocalizer.ratio, built_in.relocalizer.ratio);
  EXPECT_EQ(shipped.relocalizer.keyframes, built_in.relocalizer.keyframes);
  EXPECT_EQ(shipped.relocalizer.min_inliers, built_in.relocalizer.min_inliers);
  EXPECT_EQ(shipped.prior.fusion.confidence_gain, built_in.prior.fusion.confidence_gain);
  EXPECT_EQ(shipped.prior.fusion.max_confidence, built_in.prior.fusion.max_confidence);
  EXPECT_EQ(shipped.prior.fusion.max_depth_m, built_in.prior.fusion.max_depth_m);
  EXPECT_EQ(shipped.prior.fusion.min_confidence, built_in.prior.fusion.min_confidence);
  EXPECT_EQ(shipped.prior.fusion.min_scale_pixels, built_in.prior.fusion.min_scale_pixels);
  EXPECT_EQ(shipped.prior.view_angle_deg, built_in.prior.view_angle_deg);
  EXPECT_EQ(shipped.seed, built_in.seed);
}

TEST(Config, EmptyOrTruncatedFileIsAnErrorNamingTheMissingKey) {
  try {
    parseConfig("", "empty.yaml");
    FAIL() << "an empty file was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.input(), "empty.yaml");
  }
  // The shipped file cut after its world section: the next section is missing.
  std::ifstream in(kShipped);
  std::stringstream text;
  text << in.rdbuf();
  const std::string whole = text.str();
  const std::string cut = whole.substr(0, whole.find("\nrollout:"));
  try {
    parseConfig(cut, "cut.yaml");
    FAIL() << "a truncated file was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("cut.yaml: rollout: missing", 0), 0u) << e.what();
  }
  // One key left out of a section is named with its section.
  std::string no_budget = whole;
  no_budget.erase(no_budget.find("  budget_steps:"), no_budget.find('\n', no_budget.find("  budget_steps:")) -
                                                          no_budget.find("  budget_steps:") + 1);
  try {
    parseConfig(no_budget, "no_budget.yaml");
    FAIL() << "a file without policy.budget_steps was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("no_budget.yaml: policy.budget_steps: missing", 0), 0u) << e.what();
  }
}

TEST(Config, ExtendsMergesTheBaseUnderTheFile) {
  const auto dir = scratchFolder("extends");
  writeText(dir / "base.yaml", "extends: " + kShipped + "\npolicy:\n  budget_steps: 40\n  lambda_cov: 2\n");
  writeText(dir / "run.yaml", "extends: base.yaml\npolicy:\n  budget_steps: 60\n");
  const Config c = loadConfig((dir / "run.yaml").string());
  EXPECT_EQ(c.policy.budget_steps, 60);           // the file's own value
  EXPECT_DOUBLE_EQ(c.policy.lambda_cov, 2.0);     // its base's
  EXPECT_DOUBLE_EQ(c.policy.lambda_prog, 5.0);    // the shipped file's
  EXPECT_EQ(c.world.map, "oa_dm1");
}

TEST(Config, ExtendsCycleAndMissingBaseAreErrors) {
  const auto dir = scratchFolder("cycle");
  writeText(dir / "a.yaml", "extends: b.yaml\n");
  writeText(dir / "b.yaml", "extends: a.yaml\n");
  try {
    loadConfig((dir / "a.yaml").string());
    FAIL() << "a cycle was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a cycle"), std::string::npos) << e.what();
  }
  writeText(dir / "c.yaml", "extends: nowhere.yaml\n");
  try {
    loadConfig((dir / "c.yaml").string());
    FAIL() << "a missing base was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.input(), (dir / "nowhere.yaml").string());
  }
}

TEST(Config, OverridesGoThroughTheSameChecksAndNameTheirOrigin) {
  ConfigDocument doc = ConfigDocument::load(kShipped);
  doc.set("policy.budget_steps", "30", "--budget 30");
  doc.setAssignment("floor.enabled=false", "--set floor.enabled=false");
  const Config c = doc.parse();
  EXPECT_EQ(c.policy.budget_steps, 30);
  EXPECT_FALSE(c.floor.enabled);

  const auto errorOfOverride = [](const std::string& key, const std::string& value, const std::string& origin) {
    ConfigDocument d = ConfigDocument::load(kShipped);
    try {
      d.set(key, value, origin);
      d.parse();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  // The step cap is budget x step_cap_factor: the range check keeps it far from overflow.
  EXPECT_EQ(errorOfOverride("policy.budget_steps", "1000000000", "--budget 1000000000"),
            "--budget 1000000000: policy.budget_steps: value 1000000000 outside [1, 100000]");
  EXPECT_EQ(errorOfOverride("policy.budget_step", "3", "--set policy.budget_step=3"),
            "--set policy.budget_step=3: policy.budget_step: unknown key");
  EXPECT_EQ(errorOfOverride("world.spawn", "x", "--spawn x"), "--spawn x: world.spawn: expected a number, got 'x'");
  EXPECT_EQ(errorOfOverride("policy.budget_steps.x", "3", "--set policy.budget_steps.x=3"),
            "--set policy.budget_steps.x=3: policy.budget_steps.x: budget_steps is a value, not a section");
  ConfigDocument d = ConfigDocument::load(kShipped);
  EXPECT_THROW(d.setAssignment("policy.budget_steps", "--set policy.budget_steps"), InputError);
}

TEST(Config, ResolvedYamlReadsBackToTheSameConfig) {
  const auto dir = scratchFolder("resolved");
  writeText(dir / "run.yaml", "extends: " + kShipped + "\ncollision:\n  body_radius: 0.42\n");
  ConfigDocument doc = ConfigDocument::load((dir / "run.yaml").string());
  doc.set("world.map", "oa_dm5", "--map oa_dm5");
  writeText(dir / "resolved.yaml", doc.yaml());
  const Config c = loadConfig((dir / "resolved.yaml").string());
  EXPECT_DOUBLE_EQ(c.collision.body_radius, 0.42);
  EXPECT_EQ(c.world.map, "oa_dm5");
  EXPECT_DOUBLE_EQ(c.collision.d_near, 0.455);
  EXPECT_EQ(ConfigDocument::load((dir / "resolved.yaml").string()).yaml().find("extends"), std::string::npos);
}

TEST(Config, UnknownKeyNamesFileAndKey) {
  EXPECT_EQ(errorOf("collision:\n  body_radus: 0.3\n"), "test.yaml: collision.body_radus: unknown key");
  EXPECT_EQ(errorOf("colision:\n  body_radius: 0.3\n"), "test.yaml: colision: unknown key");
}

TEST(Config, WrongTypeNamesFileAndKey) {
  EXPECT_EQ(errorOf("policy:\n  grid_cells: many\n"),
            "test.yaml: policy.grid_cells: expected a number, got 'many'");
  EXPECT_EQ(errorOf("policy:\n  grid_cells: 12.5\n"),
            "test.yaml: policy.grid_cells: expected a number, got '12.5'");
  EXPECT_EQ(errorOf("floor:\n  enabled: maybe\n"),
            "test.yaml: floor.enabled: expected true or false, got 'maybe'");
  EXPECT_EQ(errorOf("world: 3\n"), "test.yaml: world: expected a mapping");
}

TEST(Config, OutOfRangeNamesFileKeyAndRange) {
  EXPECT_EQ(errorOf("collision:\n  body_radius: -1\n"),
            "test.yaml: collision.body_radius: value -1 outside [0, 10]");
  EXPECT_EQ(errorOf("slam:\n  backend: orb\n"),
            "test.yaml: slam.backend: 'orb' is not one of: oracle, visual");
  EXPECT_EQ(errorOf("collision:\n  height_low: 1.5\n"),
            "test.yaml: collision.height_low: must be below collision.height_high");
  EXPECT_EQ(errorOf("slam:\n  visual:\n    pnp:\n      confidence: 1.5\n"),
            "test.yaml: slam.visual.pnp.confidence: value 1.5 outside [0.01, 0.999999]");
  EXPECT_EQ(errorOf("slam:\n  visual:\n    sweep:\n      min_planes: 80\n"),
            "test.yaml: slam.visual.sweep.min_planes: must not exceed slam.visual.sweep.max_planes");
  EXPECT_EQ(errorOf("slam:\n  visual:\n    sweep:\n      windw_px: 5\n"),
            "test.yaml: slam.visual.sweep.windw_px: unknown key");
  ConfigDocument doc = ConfigDocument::fromText(overShipped(""), "test.yaml");
  doc.setAssignment("slam.visual.relocalizer.ratio=0.7", "--set slam.visual.relocalizer.ratio=0.7");
  EXPECT_EQ(doc.parse().slam.visual.relocalizer.ratio, 0.7f);
  doc.setAssignment("slam.visual.seed=-1", "--set slam.visual.seed=-1");
  try {
    doc.parse();
    FAIL() << "a negative seed was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--set slam.visual.seed=-1: slam.visual.seed: expected a number", 0), 0u)
        << e.what();
  }
}

TEST(Config, MissingFileAndBadYamlAreNamed) {
  try {
    loadConfig("/nonexistent/valerant.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.input(), "/nonexistent/valerant.yaml");
  }
  EXPECT_NE(errorOf("policy: [1, 2").find("test.yaml: invalid YAML"), std::string::npos);
  // A folder opens as an empty stream; it once read as an empty config file.
  const auto dir = scratchFolder("folder");
  try {
    loadConfig(dir.string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), dir.string() + ": is a folder, not a config file");
  }
}

TEST(Config, AKeyWithoutAValueIsNamedAsEmpty) {
  // YAML reads "key:" and --set key= as null, which the message once called a mapping.
  EXPECT_EQ(errorOf("policy:\n  budget_steps:\n"),
            "test.yaml: policy.budget_steps: expected a number, got ''");
  ConfigDocument d = ConfigDocument::load(kShipped);
  d.setAssignment("floor.enabled=", "--set floor.enabled=");
  try {
    d.parse();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--set floor.enabled=: floor.enabled: expected true or false, got ''");
  }
}

TEST(Config, WholeLevelKeysAreListsAndNumbersInRange) {
  const auto errorOfOverride = [](const std::string& key, const std::string& value) {
    ConfigDocument d = ConfigDocument::load(kShipped);
    try {
      d.set(key, value, "--set " + key + "=" + value);
      d.parse();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  ConfigDocument doc = ConfigDocument::load(kShipped);
  doc.set("policy.short_translation_frames", "[32, 16]", "--set");
  doc.set("policy.short_turn_frames", "[]", "--set");
  doc.set("policy.goal_weight", "1.5", "--set");
  doc.set("policy.yielding_objections", "[short_unclear, enters_failed]", "--set");
  const Config c = doc.parse();
  EXPECT_EQ(c.policy.yielding_objections, (std::vector<std::string>{"short_unclear", "enters_failed"}));
  EXPECT_EQ(c.policy.short_translation_frames, (std::vector<int>{32, 16}));
  EXPECT_TRUE(c.policy.short_turn_frames.empty());
  EXPECT_DOUBLE_EQ(c.policy.goal_weight, 1.5);
  EXPECT_EQ(errorOfOverride("policy.short_translation_frames", "32"),
            "--set policy.short_translation_frames=32: policy.short_translation_frames: expected a list such as "
            "[32, 16], got '32'");
  EXPECT_EQ(errorOfOverride("policy.short_translation_frames", "[32, x]"),
            "--set policy.short_translation_frames=[32, x]: policy.short_translation_frames: expected a number in "
            "the list, got 'x'");
  EXPECT_EQ(errorOfOverride("policy.short_turn_frames", "[0]"),
            "--set policy.short_turn_frames=[0]: policy.short_turn_frames: list value 0 outside [1, 10000]");
  // A short action is a prefix of uw / jq: shorter than their 57 frames.
  EXPECT_EQ(errorOfOverride("policy.short_translation_frames", "[57]"),
            "--set policy.short_translation_frames=[57]: policy.short_translation_frames: 57 frames is not "
            "shorter than rollout.horizon_frames (57)");
  EXPECT_EQ(errorOfOverride("policy.goal_weight", "-1"),
            "--set policy.goal_weight=-1: policy.goal_weight: value -1 outside [0, 1e+06]");
  EXPECT_EQ(errorOfOverride("policy.open_turn", "maybe"),
            "--set policy.open_turn=maybe: policy.open_turn: expected true or false, got 'maybe'");
  EXPECT_EQ(errorOfOverride("policy.max_cell_rise", "-0.1"),
            "--set policy.max_cell_rise=-0.1: policy.max_cell_rise: value -0.1 outside [0, 100]");
  EXPECT_EQ(errorOfOverride("policy.surface_carving_ratio", "-1"),
            "--set policy.surface_carving_ratio=-1: policy.surface_carving_ratio: value -1 outside [0, 1e+06]");
  EXPECT_EQ(errorOfOverride("policy.yielding_objections", "enters_failed"),
            "--set policy.yielding_objections=enters_failed: policy.yielding_objections: expected a list such as "
            "[enters_failed, short_unclear], got 'enters_failed'");
  EXPECT_EQ(errorOfOverride("policy.yielding_objections", "[slam_lost]"),
            "--set policy.yielding_objections=[slam_lost]: policy.yielding_objections: 'slam_lost' is not one of: "
            "enters_failed, short_unclear");
  EXPECT_EQ(errorOfOverride("policy.yielding_objections", "[short_unclear, short_unclear]"),
            "--set policy.yielding_objections=[short_unclear, short_unclear]: policy.yielding_objections: "
            "'short_unclear' is named twice");
  EXPECT_EQ(errorOfOverride("policy.goal_move", "1.5"),
            "--set policy.goal_move=1.5: policy.goal_move: expected true or false, got '1.5'");
  EXPECT_EQ(errorOfOverride("collision.see_through_frames", "-1"),
            "--set collision.see_through_frames=-1: collision.see_through_frames: value -1 outside [0, 100000]");
  EXPECT_EQ(errorOfOverride("collision.see_through_tolerance", "0"),
            "--set collision.see_through_tolerance=0: collision.see_through_tolerance: value 0 outside [0.01, 10]");
  EXPECT_EQ(errorOfOverride("collision.carve_committed_views", "-1"),
            "--set collision.carve_committed_views=-1: collision.carve_committed_views: value -1 outside [0, 100000]");
  EXPECT_EQ(errorOfOverride("collision.step_height", "-0.1"),
            "--set collision.step_height=-0.1: collision.step_height: value -0.1 outside [0, 10]");
  // Between 0 and eta_low, and from eta_high up: no step-aware cylinder.
  EXPECT_EQ(errorOfOverride("collision.step_height", "0.1"),
            "--set collision.step_height=0.1: collision.step_height: 0.1 is neither 0 (the paper's test) nor "
            "within [collision.height_low, collision.height_high) = [0.18, 1.19)");
  EXPECT_EQ(errorOfOverride("collision.step_height", "1.19"),
            "--set collision.step_height=1.19: collision.step_height: 1.19 is neither 0 (the paper's test) nor "
            "within [collision.height_low, collision.height_high) = [0.18, 1.19)");
  EXPECT_EQ(errorOfOverride("collision.step_height", "0.36"), "");
  EXPECT_EQ(errorOfOverride("collision.step_height", "0.18"), "");
  EXPECT_EQ(errorOfOverride("collision.climb_lag", "-1"),
            "--set collision.climb_lag=-1: collision.climb_lag: value -1 outside [0, 100000]");
  // The climb bound belongs to the stepped body: alone it would silently do nothing.
  EXPECT_EQ(errorOfOverride("collision.climb_lag", "3"),
            "--set collision.climb_lag=3: collision.climb_lag: bounds the stepped body's climbs, so it needs "
            "collision.step_height > 0");
  EXPECT_EQ(errorOfOverride("collision.step_count", "above_step"),
            "--set collision.step_count=above_step: collision.step_count: chooses what the stepped body counts, so it "
            "needs collision.step_height > 0");
  EXPECT_NE(errorOfOverride("collision.step_count", "over"), "");
  ConfigDocument both = ConfigDocument::load(kShipped);
  both.set("collision.step_height", "0.45", "--set collision.step_height=0.45");
  both.set("collision.climb_lag", "3", "--set collision.climb_lag=3");
  EXPECT_EQ(both.parse().collision.climb_lag, 3);
}

TEST(Config, ShippedWholeLevelOptionsAreTheBuiltInDefaults) {
  // The tests that build a Config in code run the shipped policy (docs/whole_level.md).
  const Config shipped = loadConfig(std::string(VALERANT_SOURCE_DIR) + "/config/valerant.yaml");
  const PolicyConfig built_in;
  EXPECT_EQ(shipped.policy.goal_weight, built_in.goal_weight);
  EXPECT_EQ(shipped.policy.obstacle_min_points, built_in.obstacle_min_points);
  EXPECT_EQ(shipped.policy.short_translation_frames, built_in.short_translation_frames);
  EXPECT_EQ(shipped.policy.short_turn_frames, built_in.short_turn_frames);
  EXPECT_EQ(shipped.policy.open_turn, built_in.open_turn);
  EXPECT_EQ(shipped.policy.opening_weight, built_in.opening_weight);
  EXPECT_EQ(shipped.policy.no_turn_back, built_in.no_turn_back);
  EXPECT_EQ(shipped.policy.yielding_objections, built_in.yielding_objections);
  EXPECT_EQ(shipped.policy.goal_move, built_in.goal_move);
  EXPECT_EQ(shipped.policy.max_cell_rise, built_in.max_cell_rise);
  EXPECT_EQ(shipped.policy.surface_carving_ratio, built_in.surface_carving_ratio);
  EXPECT_EQ(shipped.dead_pocket.reach_past_known_pocket, DeadPocketConfig().reach_past_known_pocket);
  EXPECT_EQ(shipped.dead_pocket.ban_rewound_headings, DeadPocketConfig().ban_rewound_headings);
  EXPECT_EQ(shipped.dead_pocket.walk_in_cell_is_turn, DeadPocketConfig().walk_in_cell_is_turn);
  EXPECT_EQ(shipped.dead_pocket.cross_failed, DeadPocketConfig().cross_failed);
  EXPECT_EQ(shipped.collision.step_height, CollisionConfig().step_height);
  EXPECT_EQ(shipped.collision.climb_lag, CollisionConfig().climb_lag);
  EXPECT_EQ(shipped.collision.see_through_frames, CollisionConfig().see_through_frames);
  EXPECT_EQ(shipped.collision.see_through_tolerance, CollisionConfig().see_through_tolerance);
  EXPECT_EQ(shipped.collision.carve_committed_views, CollisionConfig().carve_committed_views);
}

TEST(Config, LearnedWorldSectionHasTheModelsContractAndRanges) {
  const Config c = loadConfig(kShipped);
  EXPECT_EQ(c.world.backend, "quake3");
  EXPECT_EQ(c.world.learned.model, "models/world_model.onnx");
  EXPECT_EQ(c.world.learned.width, 128);
  EXPECT_EQ(c.world.learned.height, 96);
  EXPECT_EQ(c.world.learned.context_frames, 4);
  EXPECT_EQ(c.world.learned.warp, "pose_anchor");  // the shipped model v4's
  EXPECT_EQ(c.world.learned.depth_prior_model, "models/depth_prior.onnx");  // pose_anchor's
  EXPECT_EQ(errorOf("world:\n  learned:\n    warp: anchor\n"),
            "test.yaml: world.learned.warp: 'anchor' is not one of: last_frame, pose_anchor, rotation_anchor");
  EXPECT_EQ(parseConfig(overShipped("world:\n  learned:\n    warp: pose_anchor\n"), "test.yaml").world.learned.warp,
            "pose_anchor");
  EXPECT_EQ(parseConfig(overShipped("world:\n  backend: learned\n"), "test.yaml").world.backend, "learned");
  EXPECT_EQ(errorOf("world:\n  backend: video\n"), "test.yaml: world.backend: 'video' is not one of: bag, learned, quake3");
  EXPECT_EQ(errorOf("world:\n  learned:\n    context_frames: 0\n"),
            "test.yaml: world.learned.context_frames: value 0 outside [1, 64]");
  EXPECT_EQ(errorOf("world:\n  learned:\n    width: 4\n"), "test.yaml: world.learned.width: value 4 outside [8, 4096]");
  EXPECT_EQ(errorOf("world:\n  learned:\n    height: 5000\n"),
            "test.yaml: world.learned.height: value 5000 outside [8, 4096]");
  EXPECT_EQ(errorOf("world:\n  learned:\n    modle: x.onnx\n"), "test.yaml: world.learned.modle: unknown key");
}
