#include "valerant/eval/eval_report.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <sstream>

#include "valerant/common/error.h"
#include "valerant/common/output_file.h"
#include "valerant/eval/spawn_departure.h"

namespace valerant {
namespace {

namespace fs = std::filesystem;

// j[key] when j is an object that has it, else null: never throws and never inserts,
// whatever shape a report.json has.
const nlohmann::json& field(const nlohmann::json& j, const std::string& key) {
  static const nlohmann::json null;
  if (!j.is_object()) return null;
  const auto it = j.find(key);
  return it == j.end() ? null : *it;
}

bool hasNumber(const nlohmann::json& j, const char* key) { return field(j, key).is_number(); }

double number(const nlohmann::json& j, const char* key) { return hasNumber(j, key) ? field(j, key).get<double>() : 0.0; }

// A mean over the runs that record a figure; -1 when none does.
struct Mean {
  double sum = 0;
  int n = 0;
  void add(double v) {
    sum += v;
    ++n;
  }
  // Adds j[key] when it is a number.
  void addField(const nlohmann::json& j, const char* key) {
    if (hasNumber(j, key)) add(number(j, key));
  }
  double value() const { return n > 0 ? sum / n : -1; }
};

// The numbers of a JSON array; empty when it is not an array of numbers.
std::vector<double> numbers(const nlohmann::json& j) {
  std::vector<double> out;
  if (!j.is_array()) return out;
  for (const auto& v : j) {
    if (!v.is_number()) return {};
    out.push_back(v.get<double>());
  }
  return out;
}

std::string fixed(double v, int digits = 1) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

std::string ratio(double v) { return v < 0 ? "-" : fixed(v, 2); }

// A summary figure (ConfigSummary: -1 when no run records it).
std::string mean(double v, int digits = 1, const std::string& missing = "-") {
  return v < 0 ? missing : fixed(v, digits);
}

// A figure a run's report.json may lack (written before the field existed): "-", not 0.
std::string recorded(const nlohmann::json& j, const char* key, int digits = 0) {
  return hasNumber(j, key) ? fixed(number(j, key), digits) : "-";
}

// The first committed translation's step (spawn_departure.h): "none" for 0, "-" when the
// report predates the field.
std::string firstTranslationCell(const nlohmann::json& report) {
  if (!hasNumber(report, "first_translation_step")) return "-";
  return number(report, "first_translation_step") > 0 ? recorded(report, "first_translation_step") : "none";
}

// Text in a markdown table cell: no '|' that would split it, no line break.
std::string cell(std::string text) {
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\n' || text[i] == '\r') text[i] = ' ';
    if (text[i] == '|') text.insert(i++, 1, '\\');
  }
  return text;
}

// How a report.json value is described in a reason: "a string", "an array", "null".
std::string described(const nlohmann::json& v) {
  if (v.is_null()) return "null";
  const std::string type = v.type_name();
  return (type == "object" || type == "array" ? "an " : "a ") + type;
}

// The top-level and ground_truth figures the report reads (numbers, or null: not recorded).
const char* const kReportNumbers[] = {"committed_steps", "rewinds", "wall_seconds", "frames_rendered",
                                      "first_translation_step", "final_turn_streak"};
const char* const kGroundTruthNumbers[] = {
    "observed_reachable_percent", "observed_reachable_m2", "in_view_reachable_percent", "penetration_free_steps",
    "penetrations",               "discarded_penetrations", "false_rejections",         "missed_collisions",
    "predicted_colliding",        "truly_colliding",        "ate_percent",              "accuracy_median_m",
    "accuracy_p90_m",             "completeness_percent",   "clean_blocked_by_failed_region",
    "turn_steps",                 "falsely_forced_turns"};

// The mean of `curves` at every index up to the longest; a curve that ended keeps its
// last value, so the mean is over every curve at every index and never drops because
// a run stopped. Empty when there is no curve.
std::vector<double> meanCurve(const std::vector<std::vector<double>>& curves) {
  size_t longest = 0;
  for (const auto& c : curves) longest = std::max(longest, c.size());
  std::vector<double> mean(longest, 0.0);
  for (const auto& c : curves)
    for (size_t i = 0; i < longest; ++i) mean[i] += c[std::min(i, c.size() - 1)] / curves.size();
  return mean;
}

// The arrays of ground_truth.coverage_curve (coverage_curve.h) the report reads.
const char* const kCoverageCurveArrays[] = {"observed_percent", "wall_seconds"};

}  // namespace

std::string reportProblem(const nlohmann::json& report, const std::string& path) {
  if (!report.is_object()) return path + " is " + described(report) + ", not a JSON object";
  auto wrong = [&](const std::string& name, const nlohmann::json& v, const std::string& expected) {
    return path + ": field '" + name + "' is " + described(v) + ", not " + expected;
  };
  const auto& interrupted = field(report, "interrupted");
  if (!interrupted.is_null() && !interrupted.is_boolean()) return wrong("interrupted", interrupted, "a boolean");
  if (interrupted.is_boolean() && interrupted.get<bool>())
    return path + " records an interrupted run (\"interrupted\": true: stopped before its budget)";
  for (const char* key : kReportNumbers)
    if (const auto& v = field(report, key); !v.is_null() && !v.is_number()) return wrong(key, v, "a number");
  if (const auto& stages = field(report, "stage_seconds"); !stages.is_null()) {
    if (!stages.is_object()) return wrong("stage_seconds", stages, "an object");
    for (const auto& [stage, seconds] : stages.items())
      if (!seconds.is_null() && !seconds.is_number()) return wrong("stage_seconds." + stage, seconds, "a number");
  }
  const auto& g = field(report, "ground_truth");
  if (g.is_null()) return path + ": field 'ground_truth' is missing or null (the run was not evaluated)";
  if (!g.is_object()) return wrong("ground_truth", g, "an object");
  for (const char* key : kGroundTruthNumbers)
    if (const auto& v = field(g, key); !v.is_null() && !v.is_number())
      return wrong(std::string("ground_truth.") + key, v, "a number");
  if (const auto& curve = field(g, "observed_percent_by_step"); !curve.is_null()) {
    if (!curve.is_array()) return wrong("ground_truth.observed_percent_by_step", curve, "an array");
    for (size_t i = 0; i < curve.size(); ++i)
      if (!curve[i].is_number())
        return wrong("ground_truth.observed_percent_by_step[" + std::to_string(i) + "]", curve[i], "a number");
  }
  if (const auto& curve = field(g, "coverage_curve"); !curve.is_null()) {
    if (!curve.is_object()) return wrong("ground_truth.coverage_curve", curve, "an object");
    for (const char* key : kCoverageCurveArrays) {
      const std::string name = std::string("ground_truth.coverage_curve.") + key;
      const auto& values = field(curve, key);
      if (!values.is_array()) return wrong(name, values, "an array");
      for (size_t i = 0; i < values.size(); ++i)
        if (!values[i].is_number()) return wrong(name + "[" + std::to_string(i) + "]", values[i], "a number");
    }
    if (field(curve, "observed_percent").size() != field(curve, "wall_seconds").size())
      return path + ": ground_truth.coverage_curve's observed_percent and wall_seconds differ in length";
  }
  if (const auto& events = field(g, "penetration_events"); !events.is_null() && !events.is_array())
    return wrong("ground_truth.penetration_events", events, "an array");
  return "";
}

EvalResult readEvalResult(const EvalRun& run) {
  EvalResult r;
  r.run = run;
  const std::string path = run.dir + "/report.json", log = " (see " + run.dir + "/explore.log)";
  std::error_code error;
  if (!fs::exists(path, error)) {
    r.error = "no report.json" + log;
    return r;
  }
  std::ifstream in(path, std::ios::binary);
  const std::string text = in ? std::string(std::istreambuf_iterator<char>(in), {}) : "";
  if (!fs::is_regular_file(path, error) || !in || in.bad()) {
    r.error = path + " cannot be read as a file";
    return r;
  }
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
    r.error = path + " is empty: the run did not finish writing it" + log;
    return r;
  }
  nlohmann::json report;
  try {
    report = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    r.error = path + " does not parse as JSON (at byte " + std::to_string(e.byte) + " of " +
              std::to_string(text.size()) + "; truncated?)" + log;
    return r;
  }
  r.error = reportProblem(report, path);
  r.ok = r.error.empty();
  if (r.ok) r.report = std::move(report);
  return r;
}

std::vector<ConfigSummary> summarise(const std::vector<EvalResult>& results, const std::vector<std::string>& configs) {
  std::vector<ConfigSummary> out;
  for (const auto& config : configs) {
    ConfigSummary s;
    s.config = config;
    std::vector<std::vector<double>> curves, committed_curves, wall_curves;
    Mean observed_percent, in_view_percent, observed_m2, per_clean_step, penetrations, outside_world, clip_only, discarded, rewinds, false_rejections, missed,
        ate, accuracy, completeness, wall, frames_per_second, committed_steps, per_step, left_spawn,
        penetrations_per_step, final_streak, blocked_by_failed, falsely_forced;
    std::map<std::string, Mean> stages;
    // Verdicts of the runs that record both figures of a ratio.
    double predicted = 0, predicted_wrongly = 0, truly = 0, truly_missed = 0;
    for (const auto& r : results) {
      if (r.run.config != config) continue;
      if (!r.ok) {
        ++s.failed;
        continue;
      }
      ++s.runs;
      const auto& j = r.report;
      const auto& g = field(j, "ground_truth");
      observed_percent.addField(g, "observed_reachable_percent");
      in_view_percent.addField(g, "in_view_reachable_percent");
      observed_m2.addField(g, "observed_reachable_m2");
      if (hasNumber(g, "observed_reachable_m2") && hasNumber(g, "penetration_free_steps")) {
        const double clean = number(g, "penetration_free_steps");
        per_clean_step.add(clean > 0 ? number(g, "observed_reachable_m2") / clean : 0.0);
      }
      penetrations.addField(g, "penetrations");
      outside_world.addField(g, "penetrations_outside_world");
      clip_only.addField(g, "penetrations_clip_only");
      discarded.addField(g, "discarded_penetrations");
      rewinds.addField(j, "rewinds");
      false_rejections.addField(g, "false_rejections");
      missed.addField(g, "missed_collisions");
      if (hasNumber(g, "predicted_colliding") && hasNumber(g, "false_rejections")) {
        predicted += number(g, "predicted_colliding");
        predicted_wrongly += number(g, "false_rejections");
      }
      if (hasNumber(g, "truly_colliding") && hasNumber(g, "missed_collisions")) {
        truly += number(g, "truly_colliding");
        truly_missed += number(g, "missed_collisions");
      }
      committed_steps.addField(j, "committed_steps");
      if (hasNumber(j, "first_translation_step")) {
        const double first = number(j, "first_translation_step");  // 0: never translated
        left_spawn.add(first >= 1 && first <= kSpawnDepartureSteps ? 100.0 : 0.0);
      }
      if (hasNumber(j, "committed_steps") && hasNumber(g, "penetrations")) {
        const double steps = number(j, "committed_steps");
        penetrations_per_step.add(steps > 0 ? number(g, "penetrations") / steps : 0.0);
      }
      final_streak.addField(j, "final_turn_streak");
      blocked_by_failed.addField(g, "clean_blocked_by_failed_region");
      if (hasNumber(g, "turn_steps") && hasNumber(g, "falsely_forced_turns") && number(g, "turn_steps") > 0)
        falsely_forced.add(100.0 * number(g, "falsely_forced_turns") / number(g, "turn_steps"));
      if (hasNumber(j, "committed_steps") && hasNumber(g, "observed_reachable_m2")) {
        const double steps = number(j, "committed_steps");
        per_step.add(steps > 0 ? number(g, "observed_reachable_m2") / steps : 0.0);
      }
      if (const auto& seconds = field(j, "stage_seconds"); seconds.is_object())
        for (const auto& [stage, value] : seconds.items())
          if (value.is_number()) stages[stage].add(value.get<double>());
      ate.addField(g, "ate_percent");
      accuracy.addField(g, "accuracy_median_m");
      completeness.addField(g, "completeness_percent");
      wall.addField(j, "wall_seconds");
      if (hasNumber(j, "wall_seconds") && hasNumber(j, "frames_rendered")) {
        const double seconds = number(j, "wall_seconds");
        frames_per_second.add(seconds > 0 ? number(j, "frames_rendered") / seconds : 0.0);
      }
      // A run whose map never had anything to align (no keyframe fused) has no curve: it
      // stays at its final value (0) throughout, and still counts in the mean. A run that
      // records neither is not in the curve.
      if (auto curve = numbers(field(g, "observed_percent_by_step")); !curve.empty())
        curves.push_back(std::move(curve));
      else if (hasNumber(g, "observed_reachable_percent"))
        curves.push_back({number(g, "observed_reachable_percent")});
      // Runs written before the coverage curve existed are not in its means.
      if (const auto& curve = field(g, "coverage_curve"); curve.is_object()) {
        auto observed = numbers(field(curve, "observed_percent"));
        auto seconds = numbers(field(curve, "wall_seconds"));
        if (!observed.empty() && observed.size() == seconds.size()) {
          committed_curves.push_back(std::move(observed));
          wall_curves.push_back(std::move(seconds));
        }
      }
    }
    s.observed_percent = observed_percent.value();
    s.in_view_percent = in_view_percent.value();
    s.observed_m2 = observed_m2.value();
    s.observed_m2_per_clean_step = per_clean_step.value();
    s.penetrations = penetrations.value();
    s.penetrations_outside_world = outside_world.value();
    s.penetrations_clip_only = clip_only.value();
    s.discarded_penetrations = discarded.value();
    s.rewinds = rewinds.value();
    s.false_rejections = false_rejections.value();
    s.missed_collisions = missed.value();
    s.ate_percent = ate.value();
    s.accuracy_median_m = accuracy.value();
    s.completeness_percent = completeness.value();
    s.wall_seconds = wall.value();
    s.frames_per_second = frames_per_second.value();
    s.committed_steps = committed_steps.value();
    s.observed_m2_per_step = per_step.value();
    s.left_spawn_percent = left_spawn.value();
    s.penetrations_per_committed_step = penetrations_per_step.value();
    s.final_turn_streak = final_streak.value();
    s.clean_blocked_by_failed_region = blocked_by_failed.value();
    s.falsely_forced_turn_percent = falsely_forced.value();
    for (const auto& [stage, seconds] : stages) s.stage_seconds[stage] = seconds.value();
    if (predicted > 0) s.verdict_precision = (predicted - predicted_wrongly) / predicted;
    if (truly > 0) s.verdict_recall = (truly - truly_missed) / truly;
    // A run that ended early (budget of steps not used up, or a stall) keeps its last value.
    s.observed_by_step = meanCurve(curves);
    s.observed_by_committed_step = meanCurve(committed_curves);
    s.wall_seconds_by_committed_step = meanCurve(wall_curves);
    out.push_back(s);
  }
  return out;
}

namespace {

const char* const kResultsCsvHeader =
    "map,spawn,config,ok,committed_steps,rewinds,first_translation_step,observed_reachable_percent,observed_reachable_m2,"
    "penetrations,penetrations_in_solid,penetrations_outside_world,penetrations_clip_only,discarded_penetrations,penetration_free_steps,false_rejections,missed_collisions,ate_percent,"
    "accuracy_median_m,accuracy_p90_m,completeness_percent,wall_seconds,frames_rendered,final_turn_streak,"
    "clean_blocked_by_failed_region,turn_steps,falsely_forced_turns,error";

// "map,spawn,config" of a results.csv row: what identifies its run.
std::string runKey(const std::string& row) {
  size_t third_comma = row.find(',');
  for (int i = 0; i < 2 && third_comma != std::string::npos; ++i) third_comma = row.find(',', third_comma + 1);
  return row.substr(0, third_comma);
}

// The rows of an existing results.csv whose runs are not in `results`. A file of another
// format is moved aside (PATH.previous, or .previous.2, ... if taken) instead of being
// merged or overwritten.
std::vector<std::string> rowsOfOtherRuns(const std::string& path, const std::vector<EvalResult>& results) {
  std::ifstream in(path);
  std::string header;
  if (!in || !std::getline(in, header)) return {};
  if (header != kResultsCsvHeader) {
    in.close();
    std::string aside = path + ".previous";
    for (int n = 2; std::filesystem::exists(aside); ++n) aside = path + ".previous." + std::to_string(n);
    std::filesystem::rename(path, aside);
    return {};
  }
  std::set<std::string> current;
  for (const auto& r : results) current.insert(r.run.map + ',' + std::to_string(r.run.spawn) + ',' + r.run.config);
  std::vector<std::string> kept;
  for (std::string row; std::getline(in, row);)
    if (!row.empty() && !current.count(runKey(row))) kept.push_back(row);
  return kept;
}

// A quoted CSV field: quotes doubled, line breaks as spaces.
std::string csvQuoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += "\"\"";
    else out += (c == '\n' || c == '\r') ? ' ' : c;
  }
  return out + "\"";
}

}  // namespace

void writeResultsCsv(const std::string& path, const std::vector<EvalResult>& results) {
  const std::vector<std::string> others = rowsOfOtherRuns(path, results);
  std::ostringstream out;
  out << kResultsCsvHeader << "\n";
  for (const auto& r : results) {
    const auto& j = r.report;
    const auto& g = field(j, "ground_truth");
    // In the order of kResultsCsvHeader.
    const std::pair<const nlohmann::json*, const char*> fields[] = {
        {&j, "committed_steps"},       {&j, "rewinds"},           {&j, "first_translation_step"},
        {&g, "observed_reachable_percent"},
        {&g, "observed_reachable_m2"}, {&g, "penetrations"},      {&g, "penetrations_in_solid"},
        {&g, "penetrations_outside_world"}, {&g, "penetrations_clip_only"}, {&g, "discarded_penetrations"},
        {&g, "penetration_free_steps"}, {&g, "false_rejections"}, {&g, "missed_collisions"},
        {&g, "ate_percent"},           {&g, "accuracy_median_m"}, {&g, "accuracy_p90_m"},
        {&g, "completeness_percent"},  {&j, "wall_seconds"},      {&j, "frames_rendered"},
        {&j, "final_turn_streak"},     {&g, "clean_blocked_by_failed_region"}, {&g, "turn_steps"},
        {&g, "falsely_forced_turns"}};
    out << r.run.map << ',' << r.run.spawn << ',' << r.run.config << ',' << r.ok;
    for (const auto& [source, key] : fields) {
      out << ',';
      if (r.ok && hasNumber(*source, key)) out << number(*source, key);  // not recorded or failed: empty
    }
    out << ',' << csvQuoted(r.error) << "\n";
  }
  for (const auto& row : others) out << row << "\n";
  writeFileAtomically(path, out.str());
}

std::string penetrationEventsSection(const std::vector<EvalResult>& results, const std::string& config) {
  std::ostringstream md;
  md << "\n## Penetration events (" << config << ")\n\n"
     << "Every committed step of a " << config << " run that put the player hull inside solid (including steps a "
        "rewind later discarded), with what the collision tests saw: the most points in the body cylinder at one "
        "sample (eq. 6 needs N_occ at two consecutive samples) and the smallest central depth in camera heights "
        "(eq. 7 fires at d_near or below).\n\n";
  std::ostringstream rows;
  int runs = 0, events = 0, unrecorded = 0;
  for (const auto& r : results) {
    if (!r.ok || r.run.config != config) continue;
    ++runs;
    const auto& list = field(field(r.report, "ground_truth"), "penetration_events");
    if (!list.is_array()) {
      ++unrecorded;
      continue;
    }
    for (const auto& e : list) {
      ++events;
      rows << "| " << r.run.map << " | " << r.run.spawn << " | " << number(e, "step") << " | "
           << (field(e, "candidate").is_string() ? cell(field(e, "candidate").get<std::string>()) : "?")
           << " | " << number(e, "frames") << " | " << recorded(e, "frames_clip_only") << " | "
           << number(e, "first_frame") << " | " << number(e, "occupied_max") << " | "
           << fixed(number(e, "min_near_ratio"), 2) << " |\n";
    }
  }
  if (runs == 0)
    md << "No finished " << config << " runs.\n";
  else if (events == 0)
    md << "None.\n";
  else
    md << "| map | spawn | step | candidate | in-solid frames | of them in invisible clips | first in-solid frame | "
          "points in body | central depth / camera height |\n|---|---|---|---|---|---|---|---|---|\n"
       << rows.str();
  if (unrecorded > 0)
    md << "\n" << unrecorded << " run(s) have a report.json written before the events were recorded.\n";
  return md.str();
}

std::string markdownReport(const std::vector<ConfigSummary>& summaries, const std::vector<EvalResult>& results,
                           const std::string& command, const std::string& plots_prefix) {
  std::ostringstream md;
  md << "# valerant evaluation\n\nMade by:\n\n```\n" << command << "\n```\n\n"
     << "Means over runs (maps x spawns) per configuration. Coverage is the share of the player-reachable floor "
        "(1 m cells) the fused map observed; in view, the share the final trajectory's frames saw in their true "
        "depth, what a perfect map of the same path would observe; per clean step divides the observed area by the committed steps "
        "none of whose frames entered solid. Penetrations count committed frames whose player hull is inside "
        "solid brushes or whose centre is outside the playable world (past the world's bounds, or in a BSP leaf "
        "with no cluster: through an outer wall); the next column counts the latter alone, the one after it "
        "those whose hull is in nodraw player-clip brushes alone (they stop the player but draw nothing, so no camera "
        "sees them); discarded ones count those of committed steps that a later rewind threw away (they "
        "are not on the final trajectory, but the agent did commit them). Penetrations per committed step compare "
        "budgets. The final turn streak counts the steps at the end of a run that only turned in place or "
        "stalled, after its last translation or rewind; the next column counts translations that only the "
        "failed-region memory F rejected although they stayed out of solid: together they show a run ending "
        "trapped. The last column counts, of the steps that turned in place or stalled, those at which every translation "
        "was rejected though one of them stayed out of solid: turns the tests forced on an open way.\n\n"
     << "| config | runs | failed | reachable observed % | reachable in view % | m2 | m2 / clean step | penetrations | "
        "of them outside the world | of them in invisible clips | discarded penetrations | rewinds | false rejections | missed collisions | verdict precision | verdict recall | ATE % | accuracy median m | "
        "completeness % | s / run | frames/s | left the spawn within " << kSpawnDepartureSteps << " steps % | "
        "penetrations / committed step | final turn streak (steps) | clean translations only F rejected | "
        "turns forced on an open way % |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& s : summaries) {
    md << "| " << s.config << " | " << s.runs << " | " << s.failed << " | " << mean(s.observed_percent) << " | "
       << mean(s.in_view_percent) << " | " << mean(s.observed_m2) << " | " << mean(s.observed_m2_per_clean_step, 2) << " | " << mean(s.penetrations)
       << " | " << mean(s.penetrations_outside_world) << " | " << mean(s.penetrations_clip_only) << " | "
       << mean(s.discarded_penetrations) << " | " << mean(s.rewinds, 2) << " | " << mean(s.false_rejections)
       << " | " << mean(s.missed_collisions) << " | " << ratio(s.verdict_precision) << " | "
       << ratio(s.verdict_recall) << " | " << mean(s.ate_percent, 2) << " | " << mean(s.accuracy_median_m, 3)
       << " | " << mean(s.completeness_percent) << " | " << mean(s.wall_seconds) << " | "
       << mean(s.frames_per_second) << " | " << mean(s.left_spawn_percent, 0) << " | "
       << mean(s.penetrations_per_committed_step, 2) << " | " << mean(s.final_turn_streak) << " | "
       << mean(s.clean_blocked_by_failed_region) << " | " << mean(s.falsely_forced_turn_percent) << " |\n";
  }
  md << "\nVerdict precision: of the candidates the tests rejected as colliding, the share whose player hull "
        "really enters solid; recall: of the candidates that really enter solid, the share rejected.\n\n"
     << "## Findings (against full)\n\n";
  for (const auto& line : findings(summaries, "full")) md << "- " << line << "\n";
  md << penetrationEventsSection(results, "full");
  md << "\n## Time per run by stage (s, mean)\n\n| config | committed steps | new m2 / step |";
  std::vector<std::string> stages;
  for (const auto& s : summaries)
    for (const auto& [stage, seconds] : s.stage_seconds)
      if (std::find(stages.begin(), stages.end(), stage) == stages.end()) stages.push_back(stage);
  for (const auto& stage : stages) md << " " << stage << " |";
  md << " wall |\n|---|---|---|";
  for (size_t i = 0; i <= stages.size(); ++i) md << "---|";
  md << "\n";
  for (const auto& s : summaries) {
    md << "| " << s.config << " | " << mean(s.committed_steps) << " | " << mean(s.observed_m2_per_step) << " |";
    for (const auto& stage : stages) {
      const auto it = s.stage_seconds.find(stage);
      md << " " << (it == s.stage_seconds.end() ? std::string("-") : fixed(it->second)) << " |";
    }
    md << " " << mean(s.wall_seconds) << " |\n";
  }
  md << "\n![coverage against step](" << plots_prefix << "coverage_by_step.png)\n"
     << "![coverage against wall time](" << plots_prefix << "coverage_by_wall_time.png)\n"
     << "![penetrations](" << plots_prefix << "penetrations.png)\n"
     << "![coverage per clean step](" << plots_prefix << "coverage_per_clean_step.png)\n\n"
     << "Each plot also as SVG beside its PNG; the plotted numbers: [plots.json](" << plots_prefix
     << "plots.json).\n\n## Runs\n\n"
     << "Top-down maps of every run, one sheet per configuration: ";
  for (const auto& s : summaries) md << "[" << s.config << "](" << plots_prefix << "topdowns_" << s.config << ".png) ";
  md << "\n\n| map | spawn | config | reachable observed % | reachable in view % | m2 | committed steps | penetrations | "
        "of them outside the world | of them in invisible clips | discarded penetrations | rewinds | "
        "first translation (step) | final turn streak |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : results) {
    if (!r.ok) {
      md << "| " << r.run.map << " | " << r.run.spawn << " | " << r.run.config << " | failed: " << cell(r.error)
         << " | | | | | | | | | | |\n";
      continue;
    }
    const auto& g = field(r.report, "ground_truth");
    md << "| " << r.run.map << " | " << r.run.spawn << " | " << r.run.config << " | "
       << recorded(g, "observed_reachable_percent", 1) << " | " << recorded(g, "in_view_reachable_percent", 1) << " | "
       << recorded(g, "observed_reachable_m2") << " | "
       << recorded(r.report, "committed_steps") << " | " << recorded(g, "penetrations") << " | "
       << recorded(g, "penetrations_outside_world") << " | " << recorded(g, "penetrations_clip_only") << " | "
       << recorded(g, "discarded_penetrations") << " | " << recorded(r.report, "rewinds") << " | "
       << firstTranslationCell(r.report) << " | " << recorded(r.report, "final_turn_streak") << " |\n";
  }
  return md.str();
}

std::vector<std::string> findings(const std::vector<ConfigSummary>& summaries, const std::string& reference) {
  const auto ref = std::find_if(summaries.begin(), summaries.end(),
                                [&](const ConfigSummary& s) { return s.config == reference; });
  if (ref == summaries.end() || ref->runs == 0) return {"no finished runs of " + reference + " to compare with"};
  std::vector<std::string> out;
  const std::string unrecorded = "(not recorded)";
  out.push_back(reference + ": " + mean(ref->penetrations, 2, unrecorded) + " penetrating committed frames per run" +
                (ref->penetrations == 0 ? " (none)" : "") + ", " +
                mean(ref->observed_m2_per_clean_step, 2, unrecorded) +
                " m2 of reachable floor per penetration-free step.");
  for (const auto& s : summaries) {
    if (s.config == reference) continue;
    if (s.runs == 0) {
      out.push_back(s.config + ": no finished runs.");
      continue;
    }
    // A figure that one side does not record is not compared.
    const bool coverage_known = ref->observed_m2_per_clean_step >= 0 && s.observed_m2_per_clean_step >= 0;
    const bool better_coverage = ref->observed_m2_per_clean_step > s.observed_m2_per_clean_step;
    std::string line = s.config + ": " + mean(s.observed_m2_per_clean_step, 2, unrecorded) + " m2 per clean step (" +
                       (!coverage_known ? "not compared"
                                        : reference + (better_coverage ? " is better" : " is NOT better")) +
                       "), " + mean(s.penetrations, 2, unrecorded) + " penetrations per run (";
    if (ref->penetrations < 0 || s.penetrations < 0) line += "not compared)";
    else if (s.penetrations > ref->penetrations) line += "more than " + reference + ")";
    else if (s.penetrations < ref->penetrations) line += "fewer than " + reference + ")";
    else line += "as many as " + reference + ")";
    line += ", " + mean(s.observed_percent, 1, unrecorded) + "% of reachable floor observed vs " +
            mean(ref->observed_percent, 1, unrecorded) + "%.";
    out.push_back(line);
  }
  return out;
}

cv::Mat topdownSheet(const std::vector<EvalResult>& results, const std::string& config, int thumbnail_px) {
  std::vector<std::pair<std::string, cv::Mat>> tiles;
  for (const auto& r : results) {
    if (r.run.config != config || !r.ok) continue;
    const std::string path = r.run.dir + "/topdown.png";
    std::error_code error;
    if (!fs::is_regular_file(path, error)) continue;  // imread would warn on stderr
    cv::Mat image = cv::imread(path);
    if (image.empty()) continue;
    const double scale = double(thumbnail_px) / std::max(image.cols, image.rows);
    cv::resize(image, image, {}, scale, scale, cv::INTER_AREA);
    tiles.emplace_back(r.run.map + " s" + std::to_string(r.run.spawn), image);
  }
  if (tiles.empty()) return {};
  const int columns = std::min<int>(5, tiles.size()), label = 18;
  const int rows = (static_cast<int>(tiles.size()) + columns - 1) / columns;
  cv::Mat sheet(rows * (thumbnail_px + label), columns * thumbnail_px, CV_8UC3, cv::Scalar::all(255));
  for (size_t i = 0; i < tiles.size(); ++i) {
    const int x = static_cast<int>(i % columns) * thumbnail_px, y = static_cast<int>(i / columns) * (thumbnail_px + label);
    const cv::Mat& tile = tiles[i].second;
    tile.copyTo(sheet(cv::Rect(x, y + label, tile.cols, tile.rows)));
    cv::putText(sheet, tiles[i].first, {x + 4, y + 13}, cv::FONT_HERSHEY_SIMPLEX, 0.42, cv::Scalar::all(0), 1, cv::LINE_AA);
  }
  return sheet;
}

}  // namespace valerant
