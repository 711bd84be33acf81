// The evaluation grid: runs, their explore options, and the per-configuration means.
#include <gtest/gtest.h>

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
  auto result = [](const std::string& config, double observed, double penetrations, double clean_steps) {
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
                  {"observed_percent_by_step", {observed / 2, observed}}}}};
    return r;
  };
  std::vector<EvalResult> results = {result("full", 20, 0, 4), result("full", 30, 0, 5), result("random", 10, 6, 2)};
  EvalResult failed;
  failed.run = {"m", 1, "random", "/o"};
  failed.error = "no report.json";
  results.push_back(failed);
  const auto s = summarise(results, {"full", "random"});
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].runs, 2);
  EXPECT_DOUBLE_EQ(s[0].observed_percent, 25.0);
  EXPECT_DOUBLE_EQ(s[0].observed_m2_per_clean_step, (200.0 / 4 + 300.0 / 5) / 2);
  EXPECT_EQ(s[0].observed_by_step, (std::vector<double>{12.5, 25.0}));
  EXPECT_DOUBLE_EQ(s[0].frames_per_second, 10.0);
  EXPECT_EQ(s[1].runs, 1);
  EXPECT_EQ(s[1].failed, 1);
  EXPECT_DOUBLE_EQ(s[1].penetrations, 6.0);
  const std::string md = markdownReport(s, results, "cmd", "");
  EXPECT_NE(md.find("| full | 2 | 0 | 25.0 |"), std::string::npos);
  EXPECT_NE(md.find("failed: no report.json"), std::string::npos);
}
