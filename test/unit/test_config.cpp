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
  EXPECT_EQ(c.policy.grid_cells, 128);
  EXPECT_EQ(c.policy.cells_per_d_fwd, 8);
  EXPECT_EQ(c.policy.budget_steps, 15);
  EXPECT_EQ(c.floor.min_support, 300);
  EXPECT_DOUBLE_EQ(c.floor.min_vertical_alignment, 0.7);
  EXPECT_DOUBLE_EQ(c.collision.body_radius, 0.21);
  EXPECT_DOUBLE_EQ(c.collision.height_low, 0.18);
  EXPECT_DOUBLE_EQ(c.collision.height_high, 1.19);
  EXPECT_DOUBLE_EQ(c.collision.min_confidence, 4.0);
  EXPECT_EQ(c.collision.n_occ, 30);
  EXPECT_EQ(c.collision.n_occ_consecutive, 2);
  EXPECT_EQ(c.collision.n_occ_immediate, 300);
  EXPECT_NEAR(c.collision.center_fraction, 1.0 / 3.0, 1e-9);
  EXPECT_DOUBLE_EQ(c.collision.d_near, 0.455);
  EXPECT_DOUBLE_EQ(c.collision.s_min_coefficient, 0.085);
  EXPECT_EQ(c.dead_pocket.rotation_only_steps, 3);
  EXPECT_EQ(c.dead_pocket.checkpoints_kept, 3);
  EXPECT_EQ(c.dead_pocket.max_rewinds, 2);
  EXPECT_EQ(c.dead_pocket.anchor_free_cells, 0);
  EXPECT_EQ(c.world.width, 320);
  EXPECT_EQ(c.world.height, 240);
  EXPECT_DOUBLE_EQ(c.world.d_fwd_units, 256);
  EXPECT_EQ(c.slam.backend, "visual");
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
}

TEST(Config, MissingFileAndBadYamlAreNamed) {
  try {
    loadConfig("/nonexistent/valerant.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.input(), "/nonexistent/valerant.yaml");
  }
  EXPECT_NE(errorOf("policy: [1, 2").find("test.yaml: invalid YAML"), std::string::npos);
}
