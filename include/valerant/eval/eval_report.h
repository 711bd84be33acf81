#pragma once
// Results of an evaluation grid: one CSV row per run, a markdown report with a table per
// configuration (means over runs), findings against a reference configuration, and a
// sheet of every run's top-down map per configuration (the plots: eval_plots.h).
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
  std::string error;       // why the run has no usable report
  nlohmann::json report;   // the run's report.json
};

// The result of `run` from its report.json. Not ok, with a reason naming the file (and
// the field), when there is none, it is empty, does not parse, or reportProblem() finds
// one. A run whose result is not ok is not done: valerant_eval runs it again.
EvalResult readEvalResult(const EvalRun& run);
// Why `report` (read from `path`) is not a run's result, naming the field; "" when it
// is: a JSON object, not interrupted ("interrupted": true: stopped before its budget), with
// a ground_truth object, and every field the report reads of the type it reads (a
// number may be null or absent: not recorded).
std::string reportProblem(const nlohmann::json& report, const std::string& path);

// Means over the ok runs of one configuration. Every figure is a mean over the runs
// whose report.json records it (null or absent in a report written before the field
// existed, or for a NaN: not counted), and -1 when none does; all of them are >= 0 otherwise.
struct ConfigSummary {
  std::string config;
  int runs = 0, failed = 0;
  double observed_percent = -1, observed_m2 = -1, observed_m2_per_clean_step = -1;
  // The reachable floor the final trajectory's frames had in view (episode_truth.h):
  // what a perfect map of the same path would observe.
  double in_view_percent = -1;
  double penetrations = -1, rewinds = -1, false_rejections = -1, missed_collisions = -1;
  // Of the penetrations, the frames whose hull centre was outside the playable world
  // (the rest, and some of these, had the hull inside solid: episode_truth.h).
  double penetrations_outside_world = -1;
  double penetrations_clip_only = -1;  // ... in invisible player-clip brushes only
  // In-solid frames of committed steps that a rewind later discarded.
  double discarded_penetrations = -1;
  double ate_percent = -1, accuracy_median_m = -1, completeness_percent = -1, wall_seconds = -1,
         frames_per_second = -1;
  double committed_steps = -1, observed_m2_per_step = -1;  // new reachable area per committed step
  // Share of the runs that committed a translation within the first kSpawnDepartureSteps
  // exploration steps (spawn_departure.h), in percent.
  double left_spawn_percent = -1;
  // Penetrations divided by committed steps, a mean over runs: comparable between budgets
  // (issue 25: a 150-step grid no worse per step than the 15-step one).
  double penetrations_per_committed_step = -1;
  // How runs end trapped (trap_figures.h): steps turning in place after the last
  // translation or rewind, and clean translations that only F rejected.
  double final_turn_streak = -1, clean_blocked_by_failed_region = -1;
  // Of the steps that turned in place or stalled, the share at which every translation was
  // rejected though one stayed out of solid (trap_figures.h forcedTurns), in percent: a
  // mean over the runs that turned at all.
  double falsely_forced_turn_percent = -1;
  // Collision verdicts against ground truth ("this candidate would enter solid"), summed
  // over every verdict of every run before dividing (micro average); -1 when undefined.
  double verdict_precision = -1, verdict_recall = -1;
  std::map<std::string, double> stage_seconds;  // mean seconds per run in each stage
  std::vector<double> observed_by_step;  // mean curve; a run that ended keeps its last value
  // Mean curves by committed step (report.json's ground_truth.coverage_curve,
  // coverage_curve.h) over the runs that record one, a run that ended keeping its last
  // values: the reachable floor observed, and the wall seconds spent to get there.
  std::vector<double> observed_by_committed_step, wall_seconds_by_committed_step;
};

std::vector<ConfigSummary> summarise(const std::vector<EvalResult>& results, const std::vector<std::string>& configs);
// One row per result, then the rows of an existing file at `path` for runs not among
// `results` (a report of a subset of a grid does not drop the rest of the grid's rows).
// A figure the report does not record, and every figure of a failed run, is an empty cell.
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

}  // namespace valerant
