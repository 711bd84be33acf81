#pragma once
// The plots of an evaluation report (coverage against step and against wall time,
// penetrations and coverage per penetration-free step by configuration), drawn by matplotlib: the report writes
// the plotted data as plots.json into the report's image folder and runs
// scripts/plot_eval.py on it, which writes each plot as PNG and SVG beside it.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "valerant/eval/eval_report.h"

namespace valerant {

// The data the plots show (the format is plot_eval.py's docstring): per configuration
// its mean coverage curves (% of the reachable floor observed after each step; and
// after each committed step against the wall seconds spent, empty for runs written
// before report.json had a coverage_curve) and the bar values, null where no run
// records the figure.
nlohmann::json evalPlotData(const std::vector<ConfigSummary>& summaries);

// scripts/plot_eval.py of the package folder (package_dir.h), found as
// config/valerant.yaml is: the source tree, or share/valerant once installed.
std::string plotScriptPath();
// Debian's interpreter: python3-matplotlib is installed for it.
inline constexpr const char* kPlotPython = "/usr/bin/python3";

// Writes `folder`/plots.json and runs `script` on it with `python`: `folder` then holds
// coverage_by_step, coverage_by_wall_time, penetrations and coverage_per_clean_step as
// .png and .svg. Throws
// InputError naming the script when it or the interpreter is missing, or the script
// fails (matplotlib missing: its message says so).
void drawEvalPlots(const std::vector<ConfigSummary>& summaries, const std::string& folder,
                   const std::string& script = plotScriptPath(), const std::string& python = kPlotPython);

}  // namespace valerant
