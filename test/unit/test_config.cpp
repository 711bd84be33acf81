// Config loading: the shipped file matches the paper, and every kind of mistake is
// reported with the file and the key.
#include <gtest/gtest.h>

#include "valerant/common/error.h"
#include "valerant/config/config.h"

using namespace valerant;

namespace {

std::string errorOf(const std::string& yaml) {
  try {
    parseConfig(yaml, "test.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

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

TEST(Config, EmptyTextKeepsDefaults) {
  const Config c = parseConfig("", "empty.yaml");
  EXPECT_EQ(c.policy.budget_steps, 15);
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
