#pragma once
// Results of an evaluation grid: one CSV row per run, a markdown report with a table per
// configuration (means over runs), findings against a reference configuration, and
// images drawn with OpenCV (coverage against step, penetrations and coverage per
// penetration-free step by configuration, a sheet of every run's top-down map).
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <map>
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
  // In-solid frames of committed steps that a rewind later discarded, mean over the runs
  // whose report.json records them (written before the field existed: not counted); -1
  // when none does.
  double discarded_penetrations = -1;
  double ate_percent = 0, accuracy_median_m = 0, completeness_percent = 0, wall_seconds = 0, frames_per_second = 0;
  double committed_steps = 0, observed_m2_per_step = 0;  // new reachable area per committed step
  // Collision verdicts against ground truth ("this candidate would enter solid"), summed
  // over every verdict of every run before dividing (micro average); -1 when undefined.
  double verdict_precision = -1, verdict_recall = -1;
  std::map<std::string, double> stage_seconds;  // mean seconds per run in each stage
  std::vector<double> observed_by_step;  // mean curve; a run that ended keeps its last value
};

std::vector<ConfigSummary> summarise(const std::vector<EvalResult>& results, const std::vector<std::string>& configs);
// One row per result, then the rows of an existing file at `path` for runs not among
// `results` (a report of a subset of a grid does not drop the rest of the grid's rows).
void writeResultsCsv(const std::string& path, const std::vector<EvalResult>& results);
// The markdown section listing every penetration event (report.json's
// ground_truth.penetration_events) of the runs of `config`.
std::string penetrationEventsSection(const std::vector<EvalResult>& results, const std::string& config);
std::string markdownReport(const std::vector<ConfigSummary>& summaries, const std::vector<EvalResult>& results,
                           const std::string& command, const std::string& plots_prefix);
// Plain sentences comparing every configuration with `reference` (coverage per clean
// step, penetrations, coverage), for the report's findings section.
std::vector<std::string> findings(const std::vector<ConfigSummary>& summaries, const std::string& reference);
// Every finished run of `config` as a labelled thumbnail of its topdown.png (BGR; empty
// when no run has one).
cv::Mat topdownSheet(const std::vector<EvalResult>& results, const std::string& config, int thumbnail_px);
cv::Mat plotCoverageCurves(const std::vector<ConfigSummary>& summaries);  // BGR
cv::Mat plotBars(const std::vector<ConfigSummary>& summaries, double ConfigSummary::*value, const std::string& title);

}  // namespace valerant
