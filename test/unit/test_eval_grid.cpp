// The evaluation grid: runs, their explore options, and the per-configuration means.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "valerant/common/error.h"
#include "valerant/eval/eval_report.h"

using namespace valerant;

TEST(EvalGrid, RunsAndOptions) {
  const auto runs = makeEvalGrid({"oa_dm1", "oa_dm4"}, 3, {"full", "oracle", "no-col"}, "/o");
  ASSERT_EQ(runs.size(), 18u);
  EXPECT_EQ(runs[4].dir, "/o/runs/oa_dm1-s1-oracle");
  const auto oracle = exploreArguments(runs[4], "visual", 15);
  const std::vector<std::string> expected = {"--map", "oa_dm1", "--spawn", "1", "--slam", "oracle", "--budget",
                                             "15", "--out", "/o/runs/oa_dm1-s1-oracle", "--force"};
  EXPECT_EQ(oracle, expected);  // the configuration's own SLAM replaces the grid's
  const auto no_col = exploreArguments(runs[5], "visual", 15);
  EXPECT_EQ(std::vector<std::string>(no_col.end() - 2, no_col.end()),
            (std::vector<std::string>{"--no-col-pc", "--no-col-depth"}));
  EXPECT_THROW(makeEvalGrid({"oa_dm1"}, 1, {"fast"}, "/o"), InputError);
  EXPECT_THROW(makeEvalGrid({}, 1, {"full"}, "/o"), InputError);
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
  std::vector<EvalResult> results = {discarded(result("full", 20, 0, 4), 4), discarded(result("full", 30, 0, 5), 0),
                                     nothing, result("random", 10, 6, 2, {10}), result("random", 8, 0, 2)};
  EvalResult failed;
  failed.run = {"m", 1, "random", "/o"};
  failed.error = "no report.json";
  results.push_back(failed);
  const auto s = summarise(results, {"full", "random"});
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].runs, 3);
  EXPECT_DOUBLE_EQ(s[0].observed_percent, 50.0 / 3);
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
  EXPECT_NE(md.find("| full | 3 | 0 | 16.7 |"), std::string::npos);
  EXPECT_NE(md.find("| 0.0 | 2.0 | 1.00 |"), std::string::npos);   // full: penetrations, discarded, rewinds
  EXPECT_NE(md.find("| 45.00 | 3.0 | - | 1.00 |"), std::string::npos);  // random: none recorded
  EXPECT_NE(md.find("| m | 0 | full | 20.0 | 200 | 0 | 0 | 4 | 1 |"), std::string::npos);
  EXPECT_NE(md.find("| m | 0 | full | 0.0 | 0 | 0 | 0 | - | 1 |"), std::string::npos);
  // No full report lists penetration events: the section says how many predate them.
  EXPECT_NE(md.find("3 run(s) have a report.json written before"), std::string::npos);
  EXPECT_NE(md.find("failed: no report.json"), std::string::npos);
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
                                {"first_frame", 16}, {"occupied_max", 0}, {"min_near_ratio", 4.6406}};
  const std::vector<EvalResult> results = {run(0, "full", nlohmann::json::array()), run(2, "full", {graze}),
                                           run(1, "no-col", {graze})};
  const std::string md = penetrationEventsSection(results, "full");
  EXPECT_NE(md.find("| oa_dm4 | 2 | 14 | jw@20 | 4 | 16 | 0 | 4.64 |"), std::string::npos);
  EXPECT_EQ(md.find("| oa_dm4 | 1 |"), std::string::npos);  // another configuration
  EXPECT_EQ(md.find("written before"), std::string::npos);
  EXPECT_NE(penetrationEventsSection({run(0, "full", nlohmann::json::array())}, "full").find("None."),
            std::string::npos);
  // A grid without full runs lists nothing, and does not claim that full had no events.
  const std::string without = penetrationEventsSection({run(1, "no-col", {graze})}, "full");
  EXPECT_NE(without.find("No finished full runs."), std::string::npos);
  EXPECT_EQ(without.find("None."), std::string::npos);
  // A hand-edited or truncated report: a non-string candidate, a non-object event.
  const std::string odd = penetrationEventsSection({run(0, "full", {{{"candidate", 3}, {"frames", 2}}, 7})}, "full");
  EXPECT_NE(odd.find("| oa_dm4 | 0 | 0 | ? | 2 | 0 | 0 | 0.00 |"), std::string::npos);
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
  EXPECT_EQ(lines[1].substr(0, 21), "a,1,full,1,0,0,7,0,0,");
  EXPECT_EQ(lines[2].substr(0, 9), "c,0,full,");
  EXPECT_EQ(lines[3].substr(0, 21), "a,0,full,1,0,0,5,0,0,");
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
