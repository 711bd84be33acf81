// valerant_eval: runs an evaluation grid of valerant_explore episodes in parallel
// processes and reports it.
//
//   valerant_eval --maps oa_dm1,oa_dm4 --spawns 3 --configs full,no-rf,oracle,random
//                 --out DIR [--jobs 2] [--budget 15] [--slam visual|oracle] [--config FILE]
//                 [--report-only]   (report the finished runs, start none)
//                 [--publish docs/evaluation.md]  (also write the report there, its images in
//                                                   docs/evaluation/, for committing)
//
// Resumable: a run whose report.json exists is not redone. Writes DIR/results.csv (this
// grid's rows; rows an earlier command wrote for other runs stay), DIR/evaluation.md and
// plots of this grid, shows progress (runs done / total, ETA) on stderr and
// prints one JSON summary line.
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "child_process.h"
#include "cli_args.h"
#include "valerant/config/config.h"
#include "valerant/eval/eval_report.h"

using namespace valerant;
namespace fs = std::filesystem;

namespace {

EvalResult readResult(const EvalRun& run) {
  EvalResult r;
  r.run = run;
  std::ifstream in(run.dir + "/report.json");
  if (!in) {
    r.error = "no report.json (see " + run.dir + "/explore.log)";
    return r;
  }
  try {
    in >> r.report;
    r.ok = true;
  } catch (const std::exception& e) {
    r.error = std::string("unreadable report.json: ") + e.what();
  }
  return r;
}

constexpr int kThumbnailPixels = 200;  // top-down sheet tiles: 15 runs make a 1000 x 654 px sheet

// The markdown report at `md_path` and its images in `image_folder` beside it.
void writeReport(const std::string& md_path, const std::string& image_folder, const std::string& markdown,
                 const std::map<std::string, cv::Mat>& images) {
  const fs::path dir = fs::path(md_path).parent_path() / image_folder;
  if (!dir.empty()) fs::create_directories(dir);
  std::ofstream md(md_path);
  md << markdown;
  if (!md) throw InputError(md_path, "cannot write the report");
  for (const auto& [name, image] : images)
    if (!image.empty() && !cv::imwrite((dir / name).string(), image))
      throw InputError((dir / name).string(), "cannot write the image");
}

std::string formatSeconds(double s) {
  std::ostringstream out;
  out << static_cast<int>(s) / 60 << "m" << static_cast<int>(s) % 60 << "s";
  return out.str();
}

}  // namespace

int main(int argc, char** argv) {
  try {
    tools::CliArgs args(argc, argv, {"--maps", "--spawns", "--configs", "--out", "--jobs", "--budget", "--slam", "--config",
                         "--publish"},
                        {"--report-only"});
    const Config config = loadConfig(args.get("--config", defaultConfigPath()));
    const std::string out = args.required("--out");
    const std::vector<std::string> configs = args.list("--configs", "full");
    const auto runs = makeEvalGrid(args.list("--maps", args.required("--maps")), args.integer("--spawns", 1),
                                   configs, out);
    const int jobs = args.integer("--jobs", 2);
    if (jobs < 1) throw InputError("--jobs", "must be >= 1");
    const int budget = args.integer("--budget", config.policy.budget_steps);
    const std::string slam = args.get("--slam", config.slam.backend);
    const std::string explore = tools::siblingTool("valerant_explore");

    std::vector<const EvalRun*> todo;
    for (const auto& r : runs)
      if (!fs::exists(r.dir + "/report.json") && !args.has("--report-only")) todo.push_back(&r);  // resumable
    std::cerr << "valerant_eval: " << runs.size() << " runs, " << runs.size() - todo.size() << " done already, "
              << jobs << " at a time\n";
    const auto start = std::chrono::steady_clock::now();
    std::map<pid_t, const EvalRun*> running;
    size_t next = 0, finished = 0;
    while (finished < todo.size()) {
      while (running.size() < static_cast<size_t>(jobs) && next < todo.size()) {
        const EvalRun* r = todo[next++];
        std::vector<std::string> explore_args = exploreArguments(*r, slam, budget);
        if (args.has("--config")) explore_args.insert(explore_args.end(), {"--config", args.get("--config")});
        explore_args.insert(explore_args.begin(), explore);
        fs::create_directories(r->dir);
        running[tools::startChild(explore_args, r->dir + "/summary.json", r->dir + "/explore.log")] = r;
      }
      int status = 0;
      const pid_t pid = wait(&status);
      if (pid < 0) break;
      const EvalRun* r = running[pid];
      running.erase(pid);
      ++finished;
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double eta = elapsed / finished * (todo.size() - finished);
      std::cerr << "[" << finished << "/" << todo.size() << "] " << r->map << " spawn " << r->spawn << " " << r->config
                << (WIFEXITED(status) && WEXITSTATUS(status) == 0 ? " ok" : " FAILED") << "  elapsed "
                << formatSeconds(elapsed) << ", ETA " << formatSeconds(eta) << "\n";
    }

    std::vector<EvalResult> results;
    for (const auto& r : runs) results.push_back(readResult(r));
    const auto summaries = summarise(results, configs);
    writeResultsCsv(out + "/results.csv", results);
    // The command that makes these runs: --report-only only re-summarises them.
    std::string command = "scripts/run valerant_eval";
    for (int i = 1; i < argc; ++i)
      if (std::string(argv[i]) != "--report-only") command += std::string(" ") + argv[i];
    std::map<std::string, cv::Mat> images = {
        {"coverage_by_step.png", plotCoverageCurves(summaries)},
        {"penetrations.png", plotBars(summaries, &ConfigSummary::penetrations, "penetrating committed frames per run")},
        {"coverage_per_clean_step.png", plotBars(summaries, &ConfigSummary::observed_m2_per_clean_step,
                                                 "reachable m2 observed per penetration-free step")}};
    for (const auto& c : configs) images["topdowns_" + c + ".png"] = topdownSheet(results, c, kThumbnailPixels);
    writeReport(out + "/evaluation.md", "", markdownReport(summaries, results, command, ""), images);
    if (args.has("--publish")) {
      // The committed copy: images beside it in a folder named after it, links relative.
      const fs::path md = args.get("--publish");
      const std::string folder = md.stem().string();
      writeReport(md.string(), folder, markdownReport(summaries, results, command, folder + "/"), images);
    }
    nlohmann::json summary = {{"tool", "valerant_eval"}, {"runs", runs.size()}, {"out", out}};
    int failed = 0;
    for (const auto& r : results) failed += !r.ok;
    summary["failed"] = failed;
    for (const auto& s : summaries)
      summary["configs"][s.config] = {{"observed_percent", s.observed_percent}, {"penetrations", s.penetrations},
                                      {"rewinds", s.rewinds}};
    summary["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << summary.dump() << std::endl;
    return failed ? 1 : 0;
  } catch (const std::exception& e) {
    std::cerr << "valerant_eval: error: " << e.what() << std::endl;
    return 1;
  }
}
