#include "valerant/eval/eval_report.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <sstream>

#include "valerant/common/error.h"

namespace valerant {
namespace {

bool hasNumber(const nlohmann::json& j, const char* key) { return j.contains(key) && j[key].is_number(); }

double number(const nlohmann::json& j, const char* key) { return hasNumber(j, key) ? j[key].get<double>() : 0.0; }

const cv::Scalar kPalette[] = {{40, 40, 220}, {40, 160, 40}, {220, 120, 30}, {160, 40, 160}, {30, 170, 200},
                               {120, 120, 120}, {200, 60, 120}, {60, 200, 140}, {0, 90, 200}, {140, 140, 0}};

std::string fixed(double v, int digits = 1) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

std::string ratio(double v) { return v < 0 ? "-" : fixed(v, 2); }

// A figure a run's report.json may lack (written before the field existed): "-", not 0.
std::string recorded(const nlohmann::json& j, const char* key) {
  return hasNumber(j, key) ? fixed(number(j, key), 0) : "-";
}

}  // namespace

std::vector<ConfigSummary> summarise(const std::vector<EvalResult>& results, const std::vector<std::string>& configs) {
  std::vector<ConfigSummary> out;
  for (const auto& config : configs) {
    ConfigSummary s;
    s.config = config;
    std::vector<std::vector<double>> curves;
    double predicted = 0, truly = 0, false_rejections = 0, missed = 0;
    double discarded = 0;
    int discarded_runs = 0;
    for (const auto& r : results) {
      if (r.run.config != config) continue;
      if (!r.ok) {
        ++s.failed;
        continue;
      }
      ++s.runs;
      const auto& g = r.report["ground_truth"];
      s.observed_percent += number(g, "observed_reachable_percent");
      s.observed_m2 += number(g, "observed_reachable_m2");
      const double clean = number(g, "penetration_free_steps");
      s.observed_m2_per_clean_step += clean > 0 ? number(g, "observed_reachable_m2") / clean : 0.0;
      s.penetrations += number(g, "penetrations");
      if (hasNumber(g, "discarded_penetrations")) {
        discarded += number(g, "discarded_penetrations");
        ++discarded_runs;
      }
      s.rewinds += number(r.report, "rewinds");
      s.false_rejections += number(g, "false_rejections");
      s.missed_collisions += number(g, "missed_collisions");
      predicted += number(g, "predicted_colliding");
      truly += number(g, "truly_colliding");
      false_rejections += number(g, "false_rejections");
      missed += number(g, "missed_collisions");
      const double steps = number(r.report, "committed_steps");
      s.committed_steps += steps;
      s.observed_m2_per_step += steps > 0 ? number(g, "observed_reachable_m2") / steps : 0.0;
      if (r.report.contains("stage_seconds"))
        for (const auto& [stage, seconds] : r.report["stage_seconds"].items())
          if (seconds.is_number()) s.stage_seconds[stage] += seconds.get<double>();
      s.ate_percent += number(g, "ate_percent");
      s.accuracy_median_m += number(g, "accuracy_median_m");
      s.completeness_percent += number(g, "completeness_percent");
      s.wall_seconds += number(r.report, "wall_seconds");
      const double wall = number(r.report, "wall_seconds");
      s.frames_per_second += wall > 0 ? number(r.report, "frames_rendered") / wall : 0.0;
      // A run whose map never had anything to align (no keyframe fused) has no curve: it
      // stays at its final value (0) throughout, and still counts in the mean.
      if (g.contains("observed_percent_by_step") && !g["observed_percent_by_step"].empty())
        curves.push_back(g["observed_percent_by_step"].get<std::vector<double>>());
      else
        curves.push_back({number(g, "observed_reachable_percent")});
    }
    if (s.runs > 0) {
      for (double* v : {&s.observed_percent, &s.observed_m2, &s.observed_m2_per_clean_step, &s.penetrations, &s.rewinds,
                        &s.false_rejections, &s.missed_collisions, &s.ate_percent, &s.accuracy_median_m,
                        &s.completeness_percent, &s.wall_seconds, &s.frames_per_second, &s.committed_steps,
                        &s.observed_m2_per_step})
        *v /= s.runs;
      for (auto& [stage, seconds] : s.stage_seconds) seconds /= s.runs;
    }
    if (discarded_runs > 0) s.discarded_penetrations = discarded / discarded_runs;
    if (predicted > 0) s.verdict_precision = (predicted - false_rejections) / predicted;
    if (truly > 0) s.verdict_recall = (truly - missed) / truly;
    // A run that ended early (budget of steps not used up, or a stall) keeps its last
    // value, so the mean curve is over every run at every step and never drops because
    // a run stopped.
    size_t longest = 0;
    for (const auto& c : curves) longest = std::max(longest, c.size());
    s.observed_by_step.assign(longest, 0.0);
    for (const auto& c : curves)
      for (size_t i = 0; i < longest; ++i) s.observed_by_step[i] += c[std::min(i, c.size() - 1)] / curves.size();
    out.push_back(s);
  }
  return out;
}

namespace {

const char* const kResultsCsvHeader =
    "map,spawn,config,ok,committed_steps,rewinds,observed_reachable_percent,observed_reachable_m2,"
    "penetrations,discarded_penetrations,penetration_free_steps,false_rejections,missed_collisions,ate_percent,"
    "accuracy_median_m,accuracy_p90_m,completeness_percent,wall_seconds,frames_rendered,error";

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

}  // namespace

void writeResultsCsv(const std::string& path, const std::vector<EvalResult>& results) {
  const std::vector<std::string> others = rowsOfOtherRuns(path, results);
  std::ofstream out(path);
  if (!out) throw InputError(path, "cannot write results");
  out << kResultsCsvHeader << "\n";
  for (const auto& r : results) {
    const auto& j = r.report;
    const nlohmann::json g = r.ok ? j["ground_truth"] : nlohmann::json::object();
    // In the order of kResultsCsvHeader.
    const std::pair<const nlohmann::json*, const char*> fields[] = {
        {&j, "committed_steps"},       {&j, "rewinds"},           {&g, "observed_reachable_percent"},
        {&g, "observed_reachable_m2"}, {&g, "penetrations"},      {&g, "discarded_penetrations"},
        {&g, "penetration_free_steps"}, {&g, "false_rejections"}, {&g, "missed_collisions"},
        {&g, "ate_percent"},           {&g, "accuracy_median_m"}, {&g, "accuracy_p90_m"},
        {&g, "completeness_percent"},  {&j, "wall_seconds"},      {&j, "frames_rendered"}};
    out << r.run.map << ',' << r.run.spawn << ',' << r.run.config << ',' << r.ok;
    for (const auto& [source, key] : fields) out << ',' << number(*source, key);
    out << ",\"" << r.error << "\"\n";
  }
  for (const auto& row : others) out << row << "\n";
  if (!out) throw InputError(path, "cannot write results");
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
    const auto& g = r.report["ground_truth"];
    if (!g.contains("penetration_events") || !g["penetration_events"].is_array()) {
      ++unrecorded;
      continue;
    }
    for (const auto& e : g["penetration_events"]) {
      ++events;
      rows << "| " << r.run.map << " | " << r.run.spawn << " | " << number(e, "step") << " | "
           << (e.contains("candidate") && e["candidate"].is_string() ? e["candidate"].get<std::string>() : "?")
           << " | " << number(e, "frames") << " | "
           << number(e, "first_frame") << " | " << number(e, "occupied_max") << " | "
           << fixed(number(e, "min_near_ratio"), 2) << " |\n";
    }
  }
  if (runs == 0)
    md << "No finished " << config << " runs.\n";
  else if (events == 0)
    md << "None.\n";
  else
    md << "| map | spawn | step | candidate | in-solid frames | first in-solid frame | points in body | "
          "central depth / camera height |\n|---|---|---|---|---|---|---|---|\n"
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
        "(1 m cells) the fused map observed; per clean step divides the observed area by the committed steps "
        "none of whose frames entered solid. Penetrations count committed frames whose player hull is inside "
        "solid brushes; discarded ones count those of committed steps that a later rewind threw away (they "
        "are not on the final trajectory, but the agent did commit them).\n\n"
     << "| config | runs | failed | reachable observed % | m2 | m2 / clean step | penetrations | "
        "discarded penetrations | rewinds | false rejections | missed collisions | verdict precision | verdict recall | ATE % | accuracy median m | "
        "completeness % | s / run | frames/s |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& s : summaries) {
    md << "| " << s.config << " | " << s.runs << " | " << s.failed << " | " << fixed(s.observed_percent) << " | "
       << fixed(s.observed_m2) << " | " << fixed(s.observed_m2_per_clean_step, 2) << " | " << fixed(s.penetrations)
       << " | " << (s.discarded_penetrations < 0 ? std::string("-") : fixed(s.discarded_penetrations)) << " | "
       << fixed(s.rewinds, 2) << " | " << fixed(s.false_rejections) << " | " << fixed(s.missed_collisions)
       << " | " << ratio(s.verdict_precision) << " | " << ratio(s.verdict_recall) << " | " << fixed(s.ate_percent, 2) << " | " << fixed(s.accuracy_median_m, 3) << " | "
       << fixed(s.completeness_percent) << " | " << fixed(s.wall_seconds) << " | " << fixed(s.frames_per_second)
       << " |\n";
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
    md << "| " << s.config << " | " << fixed(s.committed_steps) << " | " << fixed(s.observed_m2_per_step) << " |";
    for (const auto& stage : stages) {
      const auto it = s.stage_seconds.find(stage);
      md << " " << (it == s.stage_seconds.end() ? std::string("-") : fixed(it->second)) << " |";
    }
    md << " " << fixed(s.wall_seconds) << " |\n";
  }
  md << "\n![coverage against step](" << plots_prefix << "coverage_by_step.png)\n"
     << "![penetrations](" << plots_prefix << "penetrations.png)\n"
     << "![coverage per clean step](" << plots_prefix << "coverage_per_clean_step.png)\n\n## Runs\n\n"
     << "Top-down maps of every run, one sheet per configuration: ";
  for (const auto& s : summaries) md << "[" << s.config << "](" << plots_prefix << "topdowns_" << s.config << ".png) ";
  md << "\n\n| map | spawn | config | reachable observed % | m2 | committed steps | penetrations | "
        "discarded penetrations | rewinds |\n"
        "|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : results) {
    if (!r.ok) {
      md << "| " << r.run.map << " | " << r.run.spawn << " | " << r.run.config << " | failed: " << r.error
         << " | | | | | |\n";
      continue;
    }
    const auto& g = r.report["ground_truth"];
    md << "| " << r.run.map << " | " << r.run.spawn << " | " << r.run.config << " | "
       << fixed(number(g, "observed_reachable_percent")) << " | " << fixed(number(g, "observed_reachable_m2"), 0)
       << " | " << number(r.report, "committed_steps") << " | " << number(g, "penetrations") << " | "
       << recorded(g, "discarded_penetrations") << " | " << number(r.report, "rewinds") << " |\n";
  }
  return md.str();
}

std::vector<std::string> findings(const std::vector<ConfigSummary>& summaries, const std::string& reference) {
  const auto ref = std::find_if(summaries.begin(), summaries.end(),
                                [&](const ConfigSummary& s) { return s.config == reference; });
  if (ref == summaries.end() || ref->runs == 0) return {"no finished runs of " + reference + " to compare with"};
  std::vector<std::string> out;
  out.push_back(reference + ": " + fixed(ref->penetrations, 2) + " penetrating committed frames per run" +
                (ref->penetrations == 0 ? " (none)" : "") + ", " + fixed(ref->observed_m2_per_clean_step, 2) +
                " m2 of reachable floor per penetration-free step.");
  for (const auto& s : summaries) {
    if (s.config == reference) continue;
    if (s.runs == 0) {
      out.push_back(s.config + ": no finished runs.");
      continue;
    }
    const bool better_coverage = ref->observed_m2_per_clean_step > s.observed_m2_per_clean_step;
    std::string line = s.config + ": " + fixed(s.observed_m2_per_clean_step, 2) + " m2 per clean step (" +
                       reference + (better_coverage ? " is better" : " is NOT better") + "), " +
                       fixed(s.penetrations, 2) + " penetrations per run (";
    if (s.penetrations > ref->penetrations) line += "more than " + reference + ")";
    else if (s.penetrations < ref->penetrations) line += "fewer than " + reference + ")";
    else line += "as many as " + reference + ")";
    line += ", " + fixed(s.observed_percent) + "% of reachable floor observed vs " + fixed(ref->observed_percent) + "%.";
    out.push_back(line);
  }
  return out;
}

cv::Mat topdownSheet(const std::vector<EvalResult>& results, const std::string& config, int thumbnail_px) {
  std::vector<std::pair<std::string, cv::Mat>> tiles;
  for (const auto& r : results) {
    if (r.run.config != config || !r.ok) continue;
    cv::Mat image = cv::imread(r.run.dir + "/topdown.png");
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

cv::Mat plotCoverageCurves(const std::vector<ConfigSummary>& summaries) {
  const int w = 720, h = 420, left = 60, bottom = 40, top = 30, right = 150;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar::all(255));
  size_t steps = 1;
  double top_value = 1;
  for (const auto& s : summaries) {
    steps = std::max(steps, s.observed_by_step.size());
    for (double v : s.observed_by_step) top_value = std::max(top_value, v);
  }
  top_value = std::ceil(top_value / 10) * 10;
  auto at = [&](double step, double v) {
    return cv::Point(left + static_cast<int>((w - left - right) * step / std::max<size_t>(1, steps)),
                     h - bottom - static_cast<int>((h - bottom - top) * v / top_value));
  };
  cv::line(img, at(0, 0), at(steps, 0), cv::Scalar::all(0));
  cv::line(img, at(0, 0), at(0, top_value), cv::Scalar::all(0));
  for (int t = 0; t <= 4; ++t) {
    const double v = top_value * t / 4;
    cv::putText(img, fixed(v, v == std::round(v) ? 0 : 1), at(0, v) + cv::Point(-45, 5), cv::FONT_HERSHEY_SIMPLEX, 0.4,
                cv::Scalar::all(0));
  }
  cv::putText(img, "reachable floor observed (%) by step", {left, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar::all(0));
  cv::putText(img, "step", at(steps, 0) + cv::Point(-30, 30), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar::all(0));
  for (size_t i = 0; i < summaries.size(); ++i) {
    const auto& curve = summaries[i].observed_by_step;
    const cv::Scalar colour = kPalette[i % std::size(kPalette)];
    for (size_t k = 0; k < curve.size(); ++k) {
      const cv::Point p = at(k + 1, curve[k]);
      if (k > 0) cv::line(img, at(k, curve[k - 1]), p, colour, 2, cv::LINE_AA);
      cv::circle(img, p, 2, colour, cv::FILLED);
    }
    cv::putText(img, summaries[i].config, {w - right + 10, top + 20 * static_cast<int>(i + 1)},
                cv::FONT_HERSHEY_SIMPLEX, 0.45, colour, 1, cv::LINE_AA);
  }
  return img;
}

cv::Mat plotBars(const std::vector<ConfigSummary>& summaries, double ConfigSummary::*value, const std::string& title) {
  const int bar = 50, gap = 20, left = 50, h = 360, bottom = 60, top = 40;
  const int bars_width = left + static_cast<int>(summaries.size()) * (bar + gap) + gap;
  int baseline = 0;
  const int title_width = cv::getTextSize(title, cv::FONT_HERSHEY_SIMPLEX, 0.5, 1, &baseline).width + 20;
  cv::Mat img(h, std::max({bars_width, title_width, 320}), CV_8UC3, cv::Scalar::all(255));
  double top_value = 1e-9;
  for (const auto& s : summaries) top_value = std::max(top_value, s.*value);
  cv::putText(img, title, {10, 22}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar::all(0));
  for (size_t i = 0; i < summaries.size(); ++i) {
    const double v = summaries[i].*value;
    const int x = left + static_cast<int>(i) * (bar + gap);
    const int height = static_cast<int>((h - bottom - top) * v / top_value);
    cv::rectangle(img, {x, h - bottom - height}, {x + bar, h - bottom}, kPalette[i % std::size(kPalette)], cv::FILLED);
    cv::putText(img, fixed(v, v < 10 ? 2 : 0), {x, h - bottom - height - 5}, cv::FONT_HERSHEY_SIMPLEX, 0.4,
                cv::Scalar::all(0));
    cv::putText(img, summaries[i].config, {x, h - bottom + 18}, cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar::all(0));
  }
  cv::line(img, {left - 5, h - bottom}, {img.cols - 5, h - bottom}, cv::Scalar::all(0));
  return img;
}

}  // namespace valerant
