#pragma once
// Results of an evaluation grid: one CSV row per run, a markdown report with a table per
// configuration (means over runs), and plots drawn with OpenCV (coverage against step,
// penetrations and coverage per penetration-free step by configuration).
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "valerant/eval/eval_grid.h"

namespace valerant {

struct EvalResult {
  EvalRun run;
  bool ok = false;
  std::string error;       // why the run has no report
  nlohmann::json report;   // the run's report.json
};

struct ConfigSummary {
  std::string config;
  int runs = 0, failed = 0;
  double observed_percent = 0, observed_m2 = 0, observed_m2_per_clean_step = 0;
  double penetrations = 0, rewinds = 0, false_rejections = 0, missed_collisions = 0;
  double ate_percent = 0, accuracy_median_m = 0, completeness_percent = 0, wall_seconds = 0, frames_per_second = 0;
  std::vector<double> observed_by_step;  // mean curve
};

std::vector<ConfigSummary> summarise(const std::vector<EvalResult>& results, const std::vector<std::string>& configs);
void writeResultsCsv(const std::string& path, const std::vector<EvalResult>& results);
std::string markdownReport(const std::vector<ConfigSummary>& summaries, const std::vector<EvalResult>& results,
                           const std::string& command, const std::string& plots_prefix);
cv::Mat plotCoverageCurves(const std::vector<ConfigSummary>& summaries);  // BGR
cv::Mat plotBars(const std::vector<ConfigSummary>& summaries, double ConfigSummary::*value, const std::string& title);

}  // namespace valerant
