// The evaluation grid: runs, their explore options, and the per-configuration means.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "openarena_data.h"
#include "valerant/common/error.h"
#include "valerant/config/config.h"
#include "valerant/eval/eval_report.h"

using namespace valerant;

namespace {

// results.csv's header and first row for `results`, written afresh under `name`.
std::pair<std::string, std::string> csvHeaderAndFirstRow(const std::vector<EvalResult>& results, const std::string& name) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::remove(path.c_str());
  writeResultsCsv(path, results);
  std::ifstream csv(path);
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  return {header, row};
}

}  // namespace

TEST(EvalGrid, RunsAndOptions) {
  const auto runs = makeEvalGrid({"oa_dm1", "oa_dm4"}, 3, {"full", "oracle", "no-col"}, "/o");
  ASSERT_EQ(runs.size(), 18u);
  EXPECT_EQ(runs[4].dir, "/o/runs/oa_dm1-s1-oracle");
  const auto oracle = exploreArguments(runs[4], "visual", 15);
  const std::vector<std::string> expected = {"--map", "oa_dm1", "--spawn", "1", "--slam", "visual", "--budget", "15",
                                             "--out", "/o/runs/oa_dm1-s1-oracle", "--force", "--set",
                                             "slam.backend=oracle"};
  EXPECT_EQ(oracle, expected);  // --set comes after the flags: the configuration's SLAM replaces the grid's
  const auto no_col = exploreArguments(runs[5], "visual", 15);
  EXPECT_EQ(std::vector<std::string>(no_col.end() - 4, no_col.end()),
            (std::vector<std::string>{"--set", "collision.pointcloud_enabled=false", "--set",
                                      "collision.depth_enabled=false"}));
  EXPECT_THROW(makeEvalGrid({"oa_dm1"}, 1, {"fast"}, "/o"), InputError);
  EXPECT_THROW(makeEvalGrid({}, 1, {"full"}, "/o"), InputError);
}

TEST(EvalGrid, EveryConfigurationIsOverridesTheLoaderAccepts) {
  // Through the strict loader on the shipped file: a mistyped key or value fails here,
  // not in the middle of a grid.
  const std::string shipped = std::string(VALERANT_SOURCE_DIR) + "/config/valerant.yaml";
  auto overridden = [&](const std::string& name) {
    ConfigDocument doc = ConfigDocument::load(shipped);
    for (const auto& assignment : evalConfigOverrides(name)) doc.setAssignment(assignment, name);
    return doc.parse();
  };
  for (const auto& name : knownEvalConfigs()) EXPECT_NO_THROW(overridden(name)) << name;
  EXPECT_TRUE(overridden("full").floor.enabled);
  EXPECT_FALSE(overridden("no-rf").floor.enabled);
  EXPECT_FALSE(overridden("no-col").collision.pointcloud_enabled);
  EXPECT_FALSE(overridden("no-col").collision.depth_enabled);
  EXPECT_TRUE(overridden("no-col-pc").collision.depth_enabled);
  EXPECT_FALSE(overridden("no-dp").dead_pocket.enabled);
  EXPECT_EQ(overridden("oracle").slam.backend, "oracle");
  EXPECT_EQ(overridden("frontier").policy.kind, "frontier");
  EXPECT_THROW(evalConfigOverrides("fast"), InputError);
  const Config whole_level = overridden("whole-level");
  EXPECT_DOUBLE_EQ(whole_level.policy.goal_weight, 1.0);
  EXPECT_EQ(whole_level.policy.short_translation_frames, (std::vector<int>{32, 16}));
  EXPECT_EQ(whole_level.policy.short_turn_frames, (std::vector<int>{28}));
  EXPECT_TRUE(whole_level.policy.open_turn);
  EXPECT_DOUBLE_EQ(whole_level.policy.opening_weight, 0.5);
  EXPECT_FALSE(whole_level.policy.goal_move);  // measured, not in the row (docs/whole_level.md)
  EXPECT_DOUBLE_EQ(whole_level.policy.max_cell_rise, 0.0);
  EXPECT_DOUBLE_EQ(whole_level.collision.step_height, 0.0);
  EXPECT_TRUE(whole_level.collision.prefix_commits);  // our older additions stay
  EXPECT_EQ(whole_level.collision.committed_heights, "own_floor");
  EXPECT_EQ(overridden("full").collision.committed_heights, "branch_floor");
  const Config full = overridden("full");  // the whole-level options are off by default
  EXPECT_DOUBLE_EQ(full.policy.goal_weight, 0.0);
  EXPECT_TRUE(full.policy.short_translation_frames.empty());
  EXPECT_FALSE(full.policy.open_turn);
  EXPECT_FALSE(full.policy.goal_move);
  // The paper row is config/paper.yaml (its budget aside, which the grid sets).
  const Config paper_row = overridden("paper");
  const Config paper_file = loadConfig(std::string(VALERANT_SOURCE_DIR) + "/config/paper.yaml");
  EXPECT_EQ(paper_file.policy.budget_steps, 15);
  EXPECT_EQ(paper_file.policy.grid_cells, 128);
  EXPECT_EQ(paper_row.policy.grid_cells, paper_file.policy.grid_cells);
  EXPECT_EQ(paper_row.policy.goal_weight, paper_file.policy.goal_weight);
  EXPECT_EQ(paper_row.policy.short_translation_frames, paper_file.policy.short_translation_frames);
  EXPECT_EQ(paper_row.policy.short_turn_frames, paper_file.policy.short_turn_frames);
  EXPECT_EQ(paper_row.policy.open_turn, paper_file.policy.open_turn);
  EXPECT_EQ(paper_row.policy.opening_weight, paper_file.policy.opening_weight);
  EXPECT_EQ(paper_row.policy.no_turn_back, paper_file.policy.no_turn_back);
  EXPECT_EQ(paper_row.policy.yielding_objections, paper_file.policy.yielding_objections);
  EXPECT_TRUE(paper_file.policy.yielding_objections.empty());
  EXPECT_EQ(paper_row.policy.goal_move, paper_file.policy.goal_move);
  EXPECT_EQ(paper_row.policy.max_cell_rise, paper_file.policy.max_cell_rise);
  EXPECT_EQ(paper_row.policy.max_progress, paper_file.policy.max_progress);
  EXPECT_DOUBLE_EQ(paper_file.policy.max_progress, 0.0);
  EXPECT_DOUBLE_EQ(full.policy.max_progress, 3.0);
  EXPECT_DOUBLE_EQ(overridden("no-motion-check").policy.max_progress, 0.0);
  EXPECT_EQ(paper_row.collision.previous_steps, paper_file.collision.previous_steps);
  EXPECT_EQ(paper_row.collision.prefix_commits, paper_file.collision.prefix_commits);
  EXPECT_EQ(paper_row.collision.step_height, paper_file.collision.step_height);
  EXPECT_DOUBLE_EQ(paper_row.collision.body_radius, paper_file.collision.body_radius);
  EXPECT_DOUBLE_EQ(paper_file.collision.body_radius, 0.21);  // the paper's rho
  EXPECT_DOUBLE_EQ(full.collision.body_radius, 0.30);        // ours (docs/body_radius.md)
  EXPECT_EQ(paper_row.dead_pocket.stagnant_steps, paper_file.dead_pocket.stagnant_steps);
  EXPECT_EQ(paper_row.dead_pocket.keep_map, paper_file.dead_pocket.keep_map);
  EXPECT_FALSE(paper_file.dead_pocket.keep_map);  // the paper's rewind truncates the map
  EXPECT_EQ(paper_row.slam.depth_prior, paper_file.slam.depth_prior);
  EXPECT_EQ(paper_file.slam.depth_prior, "none");
  EXPECT_EQ(full.slam.depth_prior, "learned");  // on by default since v9 (docs/depth_prior.md)
  EXPECT_EQ(overridden("no-prior").slam.depth_prior, "none");
  EXPECT_DOUBLE_EQ(paper_file.collision.step_height, 0.0);
  EXPECT_FALSE(paper_file.collision.prefix_commits);
  EXPECT_EQ(paper_file.collision.previous_steps, 0);
  EXPECT_DOUBLE_EQ(paper_file.policy.goal_weight, 0.0);
  EXPECT_TRUE(paper_file.policy.short_translation_frames.empty());
  EXPECT_FALSE(paper_file.policy.open_turn);
}

TEST(EvalReport, MeansPerConfiguration) {
  auto result = [](const std::string& config, double observed, double penetrations, double clean_steps,
                   std::vector<double> by_step = {}) {
    if (by_step.empty()) by_step = {observed / 2, observed};
    EvalResult r;
    r.run = {"m", 0, config, "/o"};
    r.ok = true;
    r.report = {{"rewinds", 1},
                {"wall_seconds", 10},
                {"frames_rendered", 100},
                {"ground_truth",
                 {{"observed_reachable_percent", observed},
                  {"observed_reachable_m2", observed * 10},
                  {"penetrations", penetrations},
                  {"penetration_free_steps", clean_steps},
                  {"observed_percent_by_step", by_step}}}};
    return r;
  };
  // The random run stopped after one step: its 10 % holds for step 2 of the mean curve.
  // The third full run fused nothing: no curve, 0 at every step.
  auto nothing = result("full", 0, 0, 3);
  nothing.report["ground_truth"].erase("observed_percent_by_step");
  // Discarded in-solid frames: 4 and 0 in two full runs; the third report predates the
  // field, so the mean is over two runs (2), and its row shows "-", not 0.
  auto discarded = [](EvalResult r, double frames) {
    r.report["ground_truth"]["discarded_penetrations"] = frames;
    return r;
  };
  // The floor in view: recorded by one full run (40 %) only, so the mean is 40 and the
  // rows of the others show "-".
  auto in_view = result("full", 30, 0, 5);
  in_view.report["ground_truth"]["in_view_reachable_percent"] = 40.0;
  std::vector<EvalResult> results = {discarded(result("full", 20, 0, 4), 4), discarded(in_view, 0),
                                     nothing, result("random", 10, 6, 2, {10}), result("random", 8, 0, 2)};
  EvalResult failed;
  failed.run = {"m", 1, "random", "/o"};
  failed.error = "no report.json";
  results.push_back(failed);
  const auto s = summarise(results, {"full", "random"});
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].runs, 3);
  EXPECT_DOUBLE_EQ(s[0].observed_percent, 50.0 / 3);
  EXPECT_DOUBLE_EQ(s[0].in_view_percent, 40.0);
  EXPECT_DOUBLE_EQ(s[1].in_view_percent, -1.0);
  EXPECT_DOUBLE_EQ(s[0].observed_m2_per_clean_step, (200.0 / 4 + 300.0 / 5 + 0.0) / 3);
  EXPECT_EQ(s[0].observed_by_step, (std::vector<double>{(10 + 15 + 0) / 3.0, (20 + 30 + 0) / 3.0}));
  EXPECT_DOUBLE_EQ(s[0].frames_per_second, 10.0);
  EXPECT_EQ(s[1].runs, 2);
  EXPECT_EQ(s[1].failed, 1);
  EXPECT_DOUBLE_EQ(s[1].penetrations, 3.0);
  EXPECT_DOUBLE_EQ(s[0].discarded_penetrations, 2.0);
  EXPECT_DOUBLE_EQ(s[1].discarded_penetrations, -1.0);  // no random report records them
  EXPECT_EQ(s[1].observed_by_step, (std::vector<double>{(10 + 4) / 2.0, (10 + 8) / 2.0}));
  const std::string md = markdownReport(s, results, "cmd", "");
  EXPECT_NE(md.find("| full | 3 | 0 | 16.7 | 40.0 |"), std::string::npos);
  EXPECT_NE(md.find("| random | 2 | 1 | 9.0 | - |"), std::string::npos);
  EXPECT_NE(md.find("| 0.0 | - | - | 2.0 | 1.00 |"), std::string::npos);  // full: penetrations, outside, clip, discarded, rewinds
  EXPECT_NE(md.find("| 45.00 | 3.0 | - | - | - | 1.00 |"), std::string::npos);  // random: none recorded
  // These reports do not record committed_steps: "-", not 0.
  EXPECT_NE(md.find("| m | 0 | full | 20.0 | - | 200 | - | 0 | - | - | 4 | 1 |"), std::string::npos);
  EXPECT_NE(md.find("| m | 0 | full | 30.0 | 40.0 | 300 | - | 0 | - | - | 0 | 1 |"), std::string::npos);
  EXPECT_NE(md.find("| m | 0 | full | 0.0 | - | 0 | - | 0 | - | - | - | 1 |"), std::string::npos);
  // No full report lists penetration events: the section says how many predate them.
  EXPECT_NE(md.find("3 run(s) have a report.json written before"), std::string::npos);
  EXPECT_NE(md.find("failed: no report.json"), std::string::npos);
}

TEST(EvalReport, CoverageCurveMeansByCommittedStep) {
  auto run = [](nlohmann::json ground_truth) {
    EvalResult r;
    r.run = {"m", 0, "full", "/o"};
    r.ok = true;
    r.report = {{"ground_truth", ground_truth}};
    return r;
  };
  // Two runs with curves, the shorter keeping its last values (12 %, 40 s) at step 3;
  // a third written before the curve existed is in no mean.
  const auto s = summarise(
      {run({{"coverage_curve", {{"observed_percent", {4, 8, 16}}, {"wall_seconds", {10, 20, 60}}}}}),
       run({{"coverage_curve", {{"observed_percent", {6, 12}}, {"wall_seconds", {30, 40}}}}}),
       run({{"observed_reachable_percent", 50}})},
      {"full"});
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].observed_by_committed_step, (std::vector<double>{5, 10, 14}));
  EXPECT_EQ(s[0].wall_seconds_by_committed_step, (std::vector<double>{20, 30, 50}));
  EXPECT_NE(markdownReport(s, {}, "cmd", "p/").find("(p/coverage_by_wall_time.png)"), std::string::npos);
  // Old runs only: no curve at all.
  EXPECT_TRUE(summarise({run({{"observed_reachable_percent", 50}})}, {"full"})[0].observed_by_committed_step.empty());
}

TEST(EvalReport, PenetrationEventsSectionListsTheRunsEvents) {
  auto run = [](int spawn, const std::string& config, nlohmann::json events) {
    EvalResult r;
    r.run = {"oa_dm4", spawn, config, "/o"};
    r.ok = true;
    r.report = {{"ground_truth", {{"penetration_events", events}}}};
    return r;
  };
  const nlohmann::json graze = {{"step", 14},         {"candidate", "jw@20"},     {"frames", 4},
                                {"frames_clip_only", 3}, {"first_frame", 16},   {"occupied_max", 0},
                                {"min_near_ratio", 4.6406}};
  const std::vector<EvalResult> results = {run(0, "full", nlohmann::json::array()), run(2, "full", {graze}),
                                           run(1, "no-col", {graze})};
  const std::string md = penetrationEventsSection(results, "full");
  EXPECT_NE(md.find("| oa_dm4 | 2 | 14 | jw@20 | 4 | 3 | 16 | 0 | 4.64 |"), std::string::npos);
  EXPECT_EQ(md.find("| oa_dm4 | 1 |"), std::string::npos);  // another configuration
  EXPECT_EQ(md.find("written before"), std::string::npos);
  EXPECT_NE(penetrationEventsSection({run(0, "full", nlohmann::json::array())}, "full").find("None."),
            std::string::npos);
  // A grid without full runs lists nothing, and does not claim that full had no events.
  const std::string without = penetrationEventsSection({run(1, "no-col", {graze})}, "full");
  EXPECT_NE(without.find("No finished full runs."), std::string::npos);
  EXPECT_EQ(without.find("None."), std::string::npos);
  // A hand-edited or truncated report: a non-string candidate, a non-object event; an
  // event written before clip-only frames were counted shows "-" for them.
  const std::string odd = penetrationEventsSection({run(0, "full", {{{"candidate", 3}, {"frames", 2}}, 7})}, "full");
  EXPECT_NE(odd.find("| oa_dm4 | 0 | 0 | ? | 2 | - | 0 | 0 | 0.00 |"), std::string::npos);
}

TEST(EvalReport, VerdictQualityStagesAndFindings) {
  // Run A: 4 rejected candidates of which 1 was free (3 true), 5 truly colliding of which
  // 2 were let through. Run B: 2 rejected, both right; 1 truly colliding, caught.
  // Micro average: precision (6 - 1) / 6 = 5/6, recall (6 - 2) / 6 = 2/3.
  auto result = [](const std::string& config, double predicted, double truly, double false_rejections, double missed,
                   double slam_seconds, double observed_m2, double clean_steps, double penetrations) {
    EvalResult r;
    r.run = {"m", 0, config, "/o"};
    r.ok = true;
    r.report = {{"committed_steps", 10},
                {"stage_seconds", {{"slam", slam_seconds}, {"render", 1.0}}},
                {"ground_truth",
                 {{"predicted_colliding", predicted},
                  {"truly_colliding", truly},
                  {"false_rejections", false_rejections},
                  {"missed_collisions", missed},
                  {"observed_reachable_m2", observed_m2},
                  {"penetration_free_steps", clean_steps},
                  {"penetrations", penetrations}}}};
    return r;
  };
  const std::vector<EvalResult> results = {result("full", 4, 5, 1, 2, 30, 100, 10, 0),
                                           result("full", 2, 1, 0, 0, 10, 60, 10, 0),
                                           result("random", 0, 0, 0, 0, 20, 120, 4, 7)};
  const auto s = summarise(results, {"full", "random"});
  EXPECT_DOUBLE_EQ(s[0].verdict_precision, 5.0 / 6);
  EXPECT_DOUBLE_EQ(s[0].verdict_recall, 4.0 / 6);
  EXPECT_DOUBLE_EQ(s[1].verdict_precision, -1);  // nothing rejected: undefined, not 0
  EXPECT_DOUBLE_EQ(s[0].stage_seconds.at("slam"), 20.0);
  EXPECT_DOUBLE_EQ(s[0].observed_m2_per_step, (10.0 + 6.0) / 2);
  // full: (100/10 + 60/10) / 2 = 8 m2 per clean step; random: 120 / 4 = 30 with 7 penetrations.
  const auto lines = findings(s, "full");
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_NE(lines[0].find("(none)"), std::string::npos);
  EXPECT_NE(lines[1].find("30.00 m2 per clean step (full is NOT better)"), std::string::npos);
  EXPECT_NE(lines[1].find("more than full"), std::string::npos);
  const std::string md = markdownReport(s, results, "cmd", "img/");
  EXPECT_NE(md.find("| 0.83 | 0.67 |"), std::string::npos);
  EXPECT_NE(md.find("(img/topdowns_full.png)"), std::string::npos);
}

TEST(EvalReport, ResultsCsvKeepsTheRowsOfOtherRuns) {
  const std::string path = ::testing::TempDir() + "/valerant_results.csv";
  std::remove(path.c_str());
  std::remove((path + ".previous").c_str());
  std::remove((path + ".previous.2").c_str());
  auto result = [](const std::string& map, int spawn, double observed) {
    EvalResult r;
    r.run = {map, spawn, "full", "/o"};
    r.ok = true;
    r.report = {{"ground_truth", {{"observed_reachable_percent", observed}}}};
    return r;
  };
  auto rows = [&] {
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
  };
  // The whole grid, then a report of one of its runs (re-run: 7 %) and one new run.
  writeResultsCsv(path, {result("a", 0, 5), result("a", 1, 6), result("b", 0, 9)});
  writeResultsCsv(path, {result("a", 1, 7), result("c", 0, 1)});
  const auto lines = rows();
  ASSERT_EQ(lines.size(), 5u);  // header, the 2 reported rows, the 2 other runs' rows
  // Figures the reports do not record are empty cells, not 0.
  EXPECT_EQ(lines[1].substr(0, 18), "a,1,full,1,,,,7,,,");
  EXPECT_EQ(lines[2].substr(0, 9), "c,0,full,");
  EXPECT_EQ(lines[3].substr(0, 18), "a,0,full,1,,,,5,,,");
  EXPECT_EQ(lines[4].substr(0, 9), "b,0,full,");
  // A file of another format is kept beside, not merged.
  { std::ofstream(path) << "old,format\n1,2\n"; }
  writeResultsCsv(path, {result("a", 0, 5)});
  EXPECT_EQ(rows().size(), 2u);
  std::ifstream previous(path + ".previous");
  std::string header;
  std::getline(previous, header);
  EXPECT_EQ(header, "old,format");
  // A second one does not overwrite the first.
  { std::ofstream(path) << "older,format\n"; }
  writeResultsCsv(path, {result("a", 0, 5)});
  std::ifstream second(path + ".previous.2");
  std::getline(second, header);
  EXPECT_EQ(header, "older,format");
}

TEST(EvalGrid, NamesThatBecomeFoldersArePlain) {
  for (const std::string name : {"oa_dm1", "q3dm17", "map-2", "A_b.c-d", "x.bsp", "-x"})
    EXPECT_TRUE(isPlainEvalName(name)) << name;
  for (const std::string name : {"", ".", "..", "../x", "x/y", "/abs", ".hidden", "a..b", "a b", "a\\b", "x:y",
                                 "x,y", "caf\xc3\xa9", "a\nb"})
    EXPECT_FALSE(isPlainEvalName(name)) << name;
  // The error names the option and the value, before any run exists.
  auto message = [](const std::vector<std::string>& maps, const std::vector<std::string>& configs) {
    try {
      makeEvalGrid(maps, 1, configs, "/o");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message({"oa_dm1", "../x"}, {"full"}).find("--maps '../x': is not a plain map name"), std::string::npos);
  EXPECT_NE(message({"a/b"}, {"full"}).find("--maps 'a/b'"), std::string::npos);
  EXPECT_NE(message({"oa_dm1"}, {"../full"}).find("--configs '../full': is not a plain configuration name"),
            std::string::npos);
  // Named twice: both runs would write the same folder at the same time.
  EXPECT_NE(message({"oa_dm1", "oa_dm1"}, {"full"}).find("--maps 'oa_dm1': is named twice"), std::string::npos);
  EXPECT_NE(message({"oa_dm1"}, {"full", "full"}).find("--configs 'full': is named twice"), std::string::npos);
  EXPECT_EQ(message({"oa_dm1", "x.y-2"}, {"full", "oracle"}), "no error");
}

TEST(EvalGrid, SpawnIndicesAMapDoesNotHaveAreAnErrorListingTheMaps) {
  const auto runs = makeEvalGrid({"a", "b", "c"}, 3, {"full"}, "/o");
  EXPECT_NO_THROW(checkEvalSpawns(runs, {{"a", 3}, {"b", 8}, {"c", 3}}));
  EXPECT_NO_THROW(checkEvalSpawns(runs, {}));  // a map without a count is not checked
  try {
    checkEvalSpawns(runs, {{"a", 2}, {"b", 8}, {"c", 1}});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "--spawns 3: asks for spawn indices a map does not have: a has 2 spawn points (indices 0 to 1); "
              "c has 1 spawn point (index 0)");
  }
  // Only the runs to do are checked: spawn 0 alone fits a one-spawn map.
  EXPECT_NO_THROW(checkEvalSpawns({runs[0]}, {{"a", 1}}));
}

TEST(EvalGrid, InstalledSpawnCounts) {
  VALERANT_REQUIRE_OPENARENA();
  const auto counts = installedSpawnCounts({"oa_dm1"});
  ASSERT_EQ(counts.count("oa_dm1"), 1u);
  EXPECT_GT(counts.at("oa_dm1"), 0);
  try {
    installedSpawnCounts({"oa_dm1", "no_such_map"});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--maps 'no_such_map': not found"), std::string::npos);
  }
}

namespace {

// A run folder under the test's temporary folder with `text` as its report.json
// (nullptr: none).
EvalRun runWithReport(const std::string& name, const char* text) {
  const std::string dir = ::testing::TempDir() + "/valerant_eval_reports/" + name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  if (text) std::ofstream(dir + "/report.json", std::ios::binary) << text;
  return {name, 0, "full", dir};
}

}  // namespace

TEST(EvalReport, MalformedReportsAreFailedRowsWithTheirReason) {
  struct Case {
    const char* name;
    const char* text;
    std::string reason;  // in the error
  };
  const std::vector<Case> cases = {
      {"missing", nullptr, "no report.json (see "},
      {"empty", "", "report.json is empty"},
      {"blank", "  \n", "report.json is empty"},
      {"truncated", "{\"rewinds\": 1, \"ground_tr", "report.json does not parse as JSON (at byte"},
      {"array", "[]", "report.json is an array, not a JSON object"},
      {"number", "3", "report.json is a number, not a JSON object"},
      {"no_truth", "{\"rewinds\": 1}", "field 'ground_truth' is missing or null"},
      {"null_truth", "{\"ground_truth\": null}", "field 'ground_truth' is missing or null"},
      {"string_truth", "{\"ground_truth\": \"x\"}", "field 'ground_truth' is a string, not an object"},
      {"string_rewinds", "{\"ground_truth\": {}, \"rewinds\": \"2\"}", "field 'rewinds' is a string, not a number"},
      {"bool_figure", "{\"ground_truth\": {\"penetrations\": true}}",
       "field 'ground_truth.penetrations' is a boolean, not a number"},
      {"curve_item", "{\"ground_truth\": {\"observed_percent_by_step\": [1, \"x\"]}}",
       "field 'ground_truth.observed_percent_by_step[1]' is a string, not a number"},
      {"curve", "{\"ground_truth\": {\"observed_percent_by_step\": 5}}",
       "field 'ground_truth.observed_percent_by_step' is a number, not an array"},
      {"coverage_curve", "{\"ground_truth\": {\"coverage_curve\": []}}",
       "field 'ground_truth.coverage_curve' is an array, not an object"},
      {"coverage_curve_wall", "{\"ground_truth\": {\"coverage_curve\": {\"observed_percent\": [1]}}}",
       "field 'ground_truth.coverage_curve.wall_seconds' is null, not an array"},
      {"coverage_curve_item",
       "{\"ground_truth\": {\"coverage_curve\": {\"observed_percent\": [1, null], \"wall_seconds\": [1, 2]}}}",
       "field 'ground_truth.coverage_curve.observed_percent[1]' is null, not a number"},
      {"coverage_curve_lengths",
       "{\"ground_truth\": {\"coverage_curve\": {\"observed_percent\": [1], \"wall_seconds\": [1, 2]}}}",
       "coverage_curve's observed_percent and wall_seconds differ in length"},
      {"events", "{\"ground_truth\": {\"penetration_events\": {}}}",
       "field 'ground_truth.penetration_events' is an object, not an array"},
      {"stages", "{\"ground_truth\": {}, \"stage_seconds\": []}", "field 'stage_seconds' is an array, not an object"},
      {"stage", "{\"ground_truth\": {}, \"stage_seconds\": {\"slam\": \"1\"}}",
       "field 'stage_seconds.slam' is a string, not a number"},
      {"interrupted", "{\"ground_truth\": {}, \"interrupted\": true}", "records an interrupted run"},
      {"odd_interrupted", "{\"ground_truth\": {}, \"interrupted\": \"no\"}",
       "field 'interrupted' is a string, not a boolean"},
  };
  std::vector<EvalResult> results;
  for (const auto& c : cases) {
    const EvalRun run = runWithReport(c.name, c.text);
    const EvalResult r = readEvalResult(run);
    EXPECT_FALSE(r.ok) << c.name;
    EXPECT_NE(r.error.find(c.reason), std::string::npos) << c.name << ": " << r.error;
    EXPECT_NE(r.error.find(run.dir), std::string::npos) << c.name << ": the reason names the run's file";
    results.push_back(r);
  }
  // A report as valerant_explore writes it, a NaN figure (null) included, is a result.
  const EvalResult fine = readEvalResult(runWithReport(
      "fine", "{\"interrupted\": false, \"rewinds\": 0, \"ground_truth\": {\"ate_percent\": null, "
              "\"observed_reachable_percent\": 5, \"penetration_events\": [], \"observed_percent_by_step\": [5]}}"));
  EXPECT_TRUE(fine.ok) << fine.error;
  EXPECT_EQ(fine.report["ground_truth"]["observed_reachable_percent"], 5);
  results.push_back(fine);

  // None of them aborts the report: each is a failed row with its reason.
  std::vector<ConfigSummary> s;
  ASSERT_NO_THROW(s = summarise(results, {"full"}));
  EXPECT_EQ(s[0].runs, 1);
  EXPECT_EQ(s[0].failed, static_cast<int>(cases.size()));
  EXPECT_DOUBLE_EQ(s[0].observed_percent, 5.0);
  EXPECT_DOUBLE_EQ(s[0].ate_percent, -1.0);  // recorded by no run
  std::string md;
  ASSERT_NO_THROW(md = markdownReport(s, results, "cmd", ""));
  EXPECT_NE(md.find("| string_truth | 0 | full | failed: " + results[8].error + " | | | | | | |"), std::string::npos);
  const std::string path = ::testing::TempDir() + "/valerant_malformed_results.csv";
  std::remove(path.c_str());
  ASSERT_NO_THROW(writeResultsCsv(path, results));
  std::ifstream csv(path);
  std::string line;
  std::getline(csv, line);  // header
  std::getline(csv, line);
  EXPECT_EQ(line.substr(0, line.find('"')), "missing,0,full,0,,,,,,,,,,,,,,,,,,,,,,,,");  // blank, not 0
}

TEST(EvalReport, FiguresAReportDoesNotRecordAreBlankNotZero) {
  EvalResult bare;  // parses, has a ground_truth, records nothing else
  bare.run = {"m", 0, "full", "/o"};
  bare.ok = true;
  bare.report = {{"ground_truth", nlohmann::json::object()}};
  EvalResult some = bare;  // records its coverage only
  some.run.spawn = 1;
  some.report["ground_truth"]["observed_reachable_percent"] = 10;
  EvalResult quoted;  // a reason with a quote and a pipe stays inside its CSV field and table cell
  quoted.run = {"m", 2, "full", "/o"};
  quoted.error = "/o/report.json: field 'x\"y|z' is null";
  const std::vector<EvalResult> results = {bare, some, quoted};
  const auto s = summarise(results, {"full"});
  EXPECT_EQ(s[0].runs, 2);
  EXPECT_DOUBLE_EQ(s[0].observed_percent, 10.0);  // over the run that records it, not (10 + 0) / 2
  EXPECT_DOUBLE_EQ(s[0].penetrations, -1.0);
  EXPECT_DOUBLE_EQ(s[0].committed_steps, -1.0);
  EXPECT_EQ(s[0].observed_by_step, std::vector<double>{10.0});  // the bare run has no curve
  const std::string md = markdownReport(s, results, "cmd", "");
  EXPECT_NE(md.find("| full | 2 | 1 | 10.0 | - | - | - | - | - | - | - | - | - | - | - | - | - | - | - | - |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| m | 0 | full | - | - | - | - | - | - | - | - | - |"), std::string::npos);
  EXPECT_NE(md.find("| m | 1 | full | 10.0 | - | - | - | - | - | - | - | - |"), std::string::npos);
  EXPECT_NE(md.find("failed: /o/report.json: field 'x\"y\\|z' is null | | | | | | | |"), std::string::npos);
  EXPECT_NE(md.find("full: (not recorded) penetrating committed frames per run"), std::string::npos);
  EXPECT_EQ(findings(s, "full").size(), 1u);
  const std::string path = ::testing::TempDir() + "/valerant_blank_results.csv";
  std::remove(path.c_str());
  writeResultsCsv(path, results);
  std::ifstream csv(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(csv, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[1], "m,0,full,1,,,,,,,,,,,,,,,,,,,,,,,,\"\"");
  EXPECT_EQ(lines[2], "m,1,full,1,,,,10,,,,,,,,,,,,,,,,,,,,\"\"");
  EXPECT_EQ(lines[3], "m,2,full,0,,,,,,,,,,,,,,,,,,,,,,,,\"/o/report.json: field 'x\"\"y|z' is null\"");
  // A report of any shape that skipped readEvalResult still does not throw.
  EvalResult odd = bare;
  odd.report = nlohmann::json::array({1, 2});
  EvalResult odder = bare;
  odder.report = {{"ground_truth", "x"}, {"stage_seconds", 3}, {"rewinds", "1"}};
  EXPECT_NO_THROW(markdownReport(summarise({odd, odder}, {"full"}), {odd, odder}, "cmd", ""));
  EXPECT_NO_THROW(writeResultsCsv(path, {odd, odder}));
}

TEST(EvalReport, PenetrationsOutsideTheWorldAndInClipsAreAveragedAndListed) {
  auto run = [](int spawn, nlohmann::json truth) {
    EvalResult r;
    r.run = {"m", spawn, "full", "/o"};
    r.ok = true;
    r.report = {{"tool", "valerant_explore"}, {"ground_truth", truth}};
    return r;
  };
  // 6 penetrating frames, 4 of them outside the world, 1 in a clip brush alone; 2 inside
  // solid only, both in clips; one older report that does not split them: the means of
  // the outside (2) and clip-only (1.5) counts are over two runs.
  const std::vector<EvalResult> results = {
      run(0, {{"penetrations", 6},
              {"penetrations_in_solid", 2},
              {"penetrations_outside_world", 4},
              {"penetrations_clip_only", 1}}),
      run(1, {{"penetrations", 2},
              {"penetrations_in_solid", 2},
              {"penetrations_outside_world", 0},
              {"penetrations_clip_only", 2}}),
      run(2, {{"penetrations", 1}})};
  const auto s = summarise(results, {"full"});
  EXPECT_DOUBLE_EQ(s[0].penetrations, 3.0);
  EXPECT_DOUBLE_EQ(s[0].penetrations_outside_world, 2.0);
  EXPECT_DOUBLE_EQ(s[0].penetrations_clip_only, 1.5);
  const std::string md = markdownReport(s, results, "cmd", "");
  EXPECT_NE(md.find("| m | 0 | full | - | - | - | - | 6 | 4 | 1 | - | - |"), std::string::npos) << md;
  EXPECT_NE(md.find("| m | 2 | full | - | - | - | - | 1 | - | - | - | - |"), std::string::npos) << md;
}

TEST(EvalReport, RunsThatLeaveTheirSpawnWithinFiveSteps) {
  auto result = [](int spawn, nlohmann::json first_translation_step) {
    EvalResult r;
    r.run = {"m", spawn, "full", "/o"};
    r.ok = true;
    r.report = {{"rewinds", 0}, {"ground_truth", nlohmann::json::object()}};
    if (!first_translation_step.is_null()) r.report["first_translation_step"] = first_translation_step;
    return r;
  };
  // Steps 1 and 5 leave within five steps, 6 too late, 0 never; the last report predates
  // the field and is not counted: 2 of 4 runs, 50 %.
  const std::vector<EvalResult> results = {result(0, 1), result(1, 5), result(2, 6), result(3, 0),
                                           result(4, nullptr)};
  const auto s = summarise(results, {"full"});
  EXPECT_DOUBLE_EQ(s[0].left_spawn_percent, 50.0);
  const std::string md = markdownReport(s, results, "cmd", "");
  EXPECT_NE(md.find("| left the spawn within 5 steps % |"), std::string::npos);
  EXPECT_NE(md.find("| - | 50 | - | - | - | - |\n"), std::string::npos) << md;  // frames/s unrecorded, the share, then unrecorded
  EXPECT_NE(md.find("| m | 1 | full | - | - | - | - | - | - | - | - | 0 | 5 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| m | 3 | full | - | - | - | - | - | - | - | - | 0 | none |"), std::string::npos);
  EXPECT_NE(md.find("| m | 4 | full | - | - | - | - | - | - | - | - | 0 | - |"), std::string::npos);
  const auto [header, row] = csvHeaderAndFirstRow(results, "valerant_departure_results.csv");
  EXPECT_NE(header.find(",rewinds,first_translation_step,"), std::string::npos);
  EXPECT_EQ(row.substr(0, 15), "m,0,full,1,,0,1");
}

TEST(EvalReport, PenetrationsPerCommittedStepAndHowRunsEndTrapped) {
  auto run = [](int spawn, nlohmann::json report) {
    EvalResult r;
    r.run = {"m", spawn, "full", "/o"};
    r.ok = true;
    r.report = std::move(report);
    return r;
  };
  // 30 in-solid frames in 15 committed steps (2 a step) and 0 in 150 (0): 1.00 a step.
  // Final streaks of 140 and 0 steps (70), and 655 and 1 clean translations only F
  // rejected (328); the third report predates all three figures and counts in none.
  const std::vector<EvalResult> results = {
      run(0, {{"committed_steps", 15},
              {"final_turn_streak", 140},
              {"ground_truth",
               {{"penetrations", 30},
                {"clean_blocked_by_failed_region", 655},
                {"turn_steps", 8},
                {"falsely_forced_turns", 6}}}}),
      run(1, {{"committed_steps", 150},
              {"final_turn_streak", 0},
              {"ground_truth",
               {{"penetrations", 0},
                {"clean_blocked_by_failed_region", 1},
                {"turn_steps", 0},
                {"falsely_forced_turns", 0}}}}),
      run(2, {{"ground_truth", {{"penetrations", 9}}}})};
  const auto s = summarise(results, {"full"});
  EXPECT_DOUBLE_EQ(s[0].penetrations_per_committed_step, 1.0);
  EXPECT_DOUBLE_EQ(s[0].final_turn_streak, 70.0);
  EXPECT_DOUBLE_EQ(s[0].clean_blocked_by_failed_region, 328.0);
  // 6 of 8 turns forced on an open way (75 %); run 1 never turned and is not in the mean.
  EXPECT_DOUBLE_EQ(s[0].falsely_forced_turn_percent, 75.0);
  const std::string md = markdownReport(s, results, "cmd", "");
  EXPECT_NE(md.find("| penetrations / committed step | final turn streak (steps) | clean translations only F rejected | "
                    "turns forced on an open way % |"),
            std::string::npos) << md;
  EXPECT_NE(md.find("| 1.00 | 70.0 | 328.0 | 75.0 |\n"), std::string::npos) << md;
  EXPECT_NE(md.find("| - | 140 |\n"), std::string::npos) << md;  // run 0: first translation unrecorded, its streak
  EXPECT_NE(md.find("| m | 2 | full | - | - | - | - | 9 | - | - | - | - | - | - |\n"), std::string::npos) << md;
  const auto [header, row] = csvHeaderAndFirstRow(results, "valerant_trap_results.csv");
  EXPECT_NE(header.find(",frames_rendered,final_turn_streak,clean_blocked_by_failed_region,turn_steps,"
                        "falsely_forced_turns,error"),
            std::string::npos);
  EXPECT_NE(row.find(",140,655,8,6,\"\""), std::string::npos) << row;
  // A streak that is not a number names the field.
  EXPECT_NE(reportProblem({{"final_turn_streak", "long"}, {"ground_truth", nlohmann::json::object()}}, "r.json")
                .find("final_turn_streak"),
            std::string::npos);
}
