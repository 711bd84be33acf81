// The evaluation report's plots: the data they show (plots.json) and scripts/plot_eval.py
// drawing it with matplotlib as PNG and SVG; a missing script, interpreter or
// matplotlib is an error naming the script.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "valerant/common/error.h"
#include "valerant/eval/eval_plots.h"

using namespace valerant;
namespace fs = std::filesystem;

namespace {

// A fresh folder per test under gtest's temporary directory.
fs::path freshFolder() {
  const fs::path dir = fs::path(testing::TempDir()) /
                       ("valerant_eval_plots_" + std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::vector<ConfigSummary> twoConfigs() {
  ConfigSummary full, oracle;
  full.config = "full";
  full.observed_by_step = {10, 25.5, 40};
  full.penetrations = 0.5;
  full.observed_m2_per_clean_step = 12;
  oracle.config = "oracle";
  oracle.observed_by_step = {8, 30};
  oracle.penetrations = -1;  // no run records it
  oracle.observed_m2_per_clean_step = 7.25;
  full.observed_by_committed_step = {10, 40};
  full.wall_seconds_by_committed_step = {30.5, 95};
  // oracle's runs predate the coverage curve: no curve, an empty series
  return {full, oracle};
}

std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(EvalPlots, DataHoldsTheCurvesAndBarsWithNullForUnrecorded) {
  const nlohmann::json data = evalPlotData(twoConfigs());
  EXPECT_EQ(data["configs"], nlohmann::json({"full", "oracle"}));
  ASSERT_EQ(data["curves"].size(), 2u);
  const auto& curve = data["curves"][0];
  EXPECT_EQ(curve["name"], "coverage_by_step");
  EXPECT_EQ(curve["xlabel"], "step");
  EXPECT_EQ(curve["series"]["full"], nlohmann::json({10, 25.5, 40}));
  EXPECT_EQ(curve["series"]["oracle"], nlohmann::json({8, 30}));
  EXPECT_FALSE(curve.contains("x"));  // steps 1, 2, ...
  const auto& by_wall = data["curves"][1];
  EXPECT_EQ(by_wall["name"], "coverage_by_wall_time");
  EXPECT_EQ(by_wall["xlabel"], "wall seconds");
  EXPECT_EQ(by_wall["x"]["full"], nlohmann::json({30.5, 95}));
  EXPECT_EQ(by_wall["series"]["full"], nlohmann::json({10, 40}));
  EXPECT_EQ(by_wall["series"]["oracle"], nlohmann::json::array());
  ASSERT_EQ(data["bars"].size(), 2u);
  EXPECT_EQ(data["bars"][0]["name"], "penetrations");
  EXPECT_EQ(data["bars"][0]["values"]["full"], 0.5);
  EXPECT_TRUE(data["bars"][0]["values"]["oracle"].is_null());
  EXPECT_EQ(data["bars"][1]["name"], "coverage_per_clean_step");
  EXPECT_EQ(data["bars"][1]["values"]["oracle"], 7.25);
}

TEST(EvalPlots, MatplotlibDrawsEveryPlotAsPngAndSvg) {
  const fs::path dir = freshFolder();
  drawEvalPlots(twoConfigs(), dir.string());
  EXPECT_TRUE(fs::is_regular_file(dir / "plots.json"));
  for (const char* name : {"coverage_by_step", "coverage_by_wall_time", "penetrations", "coverage_per_clean_step"}) {
    const cv::Mat png = cv::imread((dir / (std::string(name) + ".png")).string());
    EXPECT_GT(png.cols, 300) << name;
    std::ifstream svg(dir / (std::string(name) + ".svg"));
    std::string head(200, '\0');
    svg.read(head.data(), head.size());
    EXPECT_NE(head.find("<svg"), std::string::npos) << name;
  }
  EXPECT_FALSE(fs::exists(dir / "plot_eval.log"));  // kept only when the script fails
}

TEST(EvalPlots, AMissingScriptOrInterpreterIsAnErrorNamingTheScript) {
  const fs::path dir = freshFolder();
  const std::string missing = (dir / "no_such_plot_eval.py").string();
  EXPECT_NE(messageOf([&] { drawEvalPlots(twoConfigs(), dir.string(), missing); }).find(missing), std::string::npos);
  const std::string message =
      messageOf([&] { drawEvalPlots(twoConfigs(), dir.string(), plotScriptPath(), "/nonexistent/python3"); });
  EXPECT_NE(message.find(plotScriptPath()), std::string::npos) << message;
  EXPECT_NE(message.find("/nonexistent/python3"), std::string::npos) << message;
}

TEST(EvalPlots, MissingMatplotlibIsAnErrorNamingTheScript) {
  // A matplotlib package that cannot be imported, first on the script's path.
  const fs::path dir = freshFolder();
  fs::create_directories(dir / "shadow" / "matplotlib");
  std::ofstream(dir / "shadow" / "matplotlib" / "__init__.py") << "raise ImportError('shadowed for the test')\n";
  const char* old = std::getenv("PYTHONPATH");
  const std::string saved = old ? old : "";
  setenv("PYTHONPATH", (dir / "shadow").c_str(), 1);
  const std::string message = messageOf([&] { drawEvalPlots(twoConfigs(), dir.string()); });
  if (old)
    setenv("PYTHONPATH", saved.c_str(), 1);
  else
    unsetenv("PYTHONPATH");
  EXPECT_NE(message.find(plotScriptPath()), std::string::npos) << message;
  EXPECT_NE(message.find("matplotlib is missing"), std::string::npos) << message;
  EXPECT_TRUE(fs::exists(dir / "plot_eval.log"));
}
