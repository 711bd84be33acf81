// valerant_eval: runs an evaluation grid of valerant_explore episodes in parallel
// processes and reports it.
//
//   valerant_eval --maps oa_dm1,oa_dm4 --spawns 3 --configs full,no-rf,oracle,random
//                 --out DIR [--jobs 2] [--budget 15] [--slam visual|oracle] [--config FILE]
//                 [--set key=value ...]   (--help: every flag)
//                 [--run-timeout SECONDS]  (per run, default 3600; 0: none)
//                 [--report-only]   (report the finished runs, start none)
//                 [--publish docs/evaluation.md]  (also write the report there, its images in
//                                                   docs/evaluation/, for committing)
//
// Map and configuration names must be plain names (run folders are named after them);
// before any run starts, every map to run must be installed and have the spawn indices
// asked for. Resumable: a run whose report.json is a finished run's (readEvalResult: it
// parses as a JSON object of the right shape, not interrupted) is not redone; any other
// run is, and until then it is a failed row with the reason. Each run is a
// valerant_explore in a process group of its own: one that runs past --run-timeout gets
// SIGTERM, then SIGKILL 10 s later, and is a failed row "timed out after N s". SIGINT or
// SIGTERM: no more runs start, the running ones get SIGTERM and are waited for, the report
// of the finished runs is written, and the exit status is 130 (SIGINT) or 143 (SIGTERM);
// a second signal kills the running ones (SIGKILL) and exits at once.
//
// Writes DIR/results.csv (this grid's rows; rows an earlier command wrote for other runs
// stay), DIR/evaluation.md and plots of this grid, shows progress (runs done / total,
// ETA) on stderr and prints one JSON summary line.
#include <signal.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "child_pool.h"
#include "child_process.h"
#include "tool_config.h"
#include "valerant/common/joined.h"
#include "valerant/common/output_file.h"
#include "valerant/config/config.h"
#include "valerant/eval/eval_grid.h"
#include "valerant/eval/eval_plots.h"
#include "valerant/eval/eval_report.h"

using namespace valerant;
namespace fs = std::filesystem;

namespace {

constexpr int kDefaultRunTimeoutSeconds = 3600;
constexpr double kTimeoutGraceSeconds = 10;  // from SIGTERM to SIGKILL of a run past its time limit
constexpr long kPollIntervalNanoseconds = 100'000'000;  // between polls of the running runs

// SIGINT / SIGTERM: the first one is handled by the main loop; a second one kills the
// runs and exits here.
volatile std::sig_atomic_t g_signals = 0;
volatile std::sig_atomic_t g_first_signal = 0;
tools::ChildPool* g_pool = nullptr;

void onSignal(int signal) {
  if (g_signals == 0) g_first_signal = signal;
  g_signals = g_signals + 1;
  if (g_signals < 2) return;
  if (g_pool) g_pool->killNow();
  constexpr char message[] = "valerant_eval: second signal: runs killed, no report written\n";
  [[maybe_unused]] const ssize_t written = write(STDERR_FILENO, message, sizeof(message) - 1);
  _exit(128 + signal);
}

// Without SA_RESTART: the main loop's sleep ends when a signal comes.
void handleStopSignals() {
  struct sigaction action {};
  action.sa_handler = onSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

std::string signalName(int signal) { return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "a signal"; }

constexpr int kThumbnailPixels = 200;  // top-down sheet tiles: 15 runs make a 1000 x 654 px sheet

// The markdown report at `md_path` and its images in `image_folder` beside it.
void writeReport(const std::string& md_path, const std::string& image_folder, const std::string& markdown,
                 const std::map<std::string, cv::Mat>& images, const std::vector<ConfigSummary>& summaries) {
  const fs::path dir = fs::path(md_path).parent_path() / image_folder;
  if (!dir.empty()) fs::create_directories(dir);
  // The images first: the report links them.
  for (const auto& [name, image] : images)
    if (!image.empty()) writeImageAtomically((dir / name).string(), image);
  drawEvalPlots(summaries, dir.empty() ? "." : dir.string());
  writeFileAtomically(md_path, markdown);
}

std::string formatSeconds(double s) {
  std::ostringstream out;
  out << static_cast<int>(s) / 60 << "m" << static_cast<int>(s) % 60 << "s";
  return out.str();
}

}  // namespace

int main(int argc, char** argv) {
  // From the start: a signal during the checks below starts no run and still reports.
  handleStopSignals();
  CLI::App app{
      "Runs an evaluation grid (maps x spawns x configurations) of valerant_explore episodes in "
      "parallel processes and reports it: results.csv, evaluation.md and plots.",
      "valerant_eval"};
  tools::useToolConventions(app);
  tools::ToolConfig tool_config(app);
  tool_config.keyFlag("--budget", "policy.budget_steps", "INT", "steps each run commits");
  tool_config.keyFlag("--slam", "slam.backend", "visual|oracle", "SLAM backend of every run");
  std::string maps_text, configs_text = "full", out, publish;
  int spawns = 1, jobs = 2, run_timeout = kDefaultRunTimeoutSeconds;
  app.add_option("--maps", maps_text, "maps, comma-separated (plain names: run folders are named after them)")
      ->type_name("LIST")
      ->required();
  tools::addInteger(app, "--spawns", spawns, "spawn points 0 to N-1 of every map", 1);
  app.add_option("--configs", configs_text, "configurations, comma-separated: " + joined(knownEvalConfigs(), ", "))
      ->type_name("LIST")
      ->capture_default_str();
  tools::addPath(app, "--out", out, "grid folder (runs/, results.csv, evaluation.md)", "DIR")->required();
  tools::addInteger(app, "--jobs", jobs, "runs at a time", 1);
  tools::addInteger(app, "--run-timeout", run_timeout, "seconds a run may take (0: no limit)", 0);
  const CLI::Option* report_only_flag = app.add_flag("--report-only", "report the finished runs, start none");
  const CLI::Option* publish_flag =
      tools::addPath(app, "--publish", publish,
                     "also write the report there (e.g. docs/evaluation.md), its images beside it", "FILE");
  return tools::runTool(app, argc, argv, [&] {
    // The grid's configuration, with --budget and --slam checked as every run will check them.
    const Config config = tool_config.document().parse();
    const std::vector<std::string> configs = tools::commaList("--configs", configs_text);
    const auto runs = tools::checkFlagValues(
        [&] { return makeEvalGrid(tools::commaList("--maps", maps_text), spawns, configs, out); });
    const int budget = config.policy.budget_steps;
    const std::string slam = config.slam.backend;
    const bool report_only = report_only_flag->count() > 0;

    std::vector<size_t> todo;  // indices into runs
    for (size_t i = 0; i < runs.size(); ++i)
      if (!report_only && !readEvalResult(runs[i]).ok) todo.push_back(i);  // resumable
    std::string explore;
    if (!todo.empty()) {
      explore = tools::siblingTool("valerant_explore");
      std::vector<EvalRun> todo_runs;
      std::vector<std::string> todo_maps;
      for (size_t i : todo) {
        todo_runs.push_back(runs[i]);
        if (std::find(todo_maps.begin(), todo_maps.end(), runs[i].map) == todo_maps.end())
          todo_maps.push_back(runs[i].map);
      }
      tools::checkFlagValues([&] { checkEvalSpawns(todo_runs, installedSpawnCounts(todo_maps)); });
    }
    std::cerr << "valerant_eval: " << runs.size() << " runs, " << runs.size() - todo.size()
              << (report_only ? " reported, none started" : " done already") << ", " << jobs << " at a time\n";
    const auto start = std::chrono::steady_clock::now();
    std::map<size_t, std::string> failures;  // this command's reason a run failed, by index into runs
    int stop_signal = 0;
    {
      tools::ChildPool pool(static_cast<size_t>(jobs), run_timeout, kTimeoutGraceSeconds);
      // The handler's pointer to the pool ends before the pool does (also on an error,
      // whose unwinding kills and reaps the running children in ~ChildPool).
      struct Registration {
        explicit Registration(tools::ChildPool* pool) { g_pool = pool; }
        ~Registration() { g_pool = nullptr; }
      } registration(&pool);
      size_t next = 0, finished = 0;
      while (pool.running() > 0 || (stop_signal == 0 && next < todo.size())) {
        if (g_signals > 0 && stop_signal == 0) {
          stop_signal = g_first_signal;
          std::cerr << "valerant_eval: " << signalName(stop_signal) << ": starting no more runs, stopping the "
                    << pool.running() << " running (a second signal kills them)\n";
          pool.terminate();
        }
        while (stop_signal == 0 && !pool.full() && next < todo.size()) {
          const EvalRun& r = runs[todo[next]];
          std::vector<std::string> explore_args = exploreArguments(r, slam, budget);
          if (tool_config.fileGiven()) explore_args.insert(explore_args.end(), {"--config", tool_config.file()});
          for (const auto& assignment : tool_config.sets())
            explore_args.insert(explore_args.end(), {"--set", assignment});
          explore_args.insert(explore_args.begin(), explore);
          fs::create_directories(r.dir);
          pool.start(todo[next++], explore_args, r.dir + "/summary.json", r.dir + "/explore.log");
        }
        const auto ended = pool.poll();
        for (const auto& e : ended) {
          const EvalRun& r = runs[e.id];
          std::string failure = pool.failure(e);
          if (e.stopped) failure = "stopped: valerant_eval got " + signalName(stop_signal);
          if (!failure.empty()) failures[e.id] = failure + " (see " + r.dir + "/explore.log)";
          if (e.timed_out) {
            // explore.log is where a failed row sends the reader: say why the log ends.
            std::ofstream(r.dir + "/explore.log", std::ios::app)
                << "valerant_eval: " << failure << ": the run's process group got SIGTERM"
                << (e.killed ? ", then SIGKILL" : "") << "\n";
          }
          ++finished;
          const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          const double eta = elapsed / finished * (todo.size() - finished);
          std::cerr << "[" << finished << "/" << todo.size() << "] " << r.map << " spawn " << r.spawn << " " << r.config
                    << (failure.empty() ? " ok" : " FAILED (" + failure + ")") << "  elapsed "
                    << formatSeconds(elapsed) << (stop_signal ? "" : ", ETA " + formatSeconds(eta)) << "\n";
        }
        if (ended.empty()) {
          // Not std::this_thread::sleep_for, which sleeps on after a signal: this ends early.
          const timespec interval{0, kPollIntervalNanoseconds};
          nanosleep(&interval, nullptr);
        }
      }
      for (size_t i = next; i < todo.size(); ++i)
        failures[todo[i]] = "not started: valerant_eval got " + signalName(stop_signal);
    }

    std::vector<EvalResult> results;
    for (size_t i = 0; i < runs.size(); ++i) {
      EvalResult result = readEvalResult(runs[i]);
      if (const auto failure = failures.find(i); failure != failures.end()) {
        // The run's own exit says more than what its folder holds (a report marked
        // interrupted, or the invalid one it was to replace).
        result.ok = false;
        result.error = failure->second;
        result.report = nlohmann::json();
      }
      results.push_back(std::move(result));
    }
    const auto summaries = summarise(results, configs);
    writeResultsCsv(out + "/results.csv", results);
    // The command that makes these runs: --report-only only re-summarises them.
    std::string command = "scripts/run valerant_eval";
    for (int i = 1; i < argc; ++i)
      if (std::string(argv[i]) != "--report-only") command += std::string(" ") + argv[i];
    std::map<std::string, cv::Mat> images;
    for (const auto& c : configs) images["topdowns_" + c + ".png"] = topdownSheet(results, c, kThumbnailPixels);
    writeReport(out + "/evaluation.md", "", markdownReport(summaries, results, command, ""), images, summaries);
    if (publish_flag->count()) {
      // The committed copy: images beside it in a folder named after it, links relative.
      const fs::path md = publish;
      const std::string folder = md.stem().string();
      writeReport(md.string(), folder, markdownReport(summaries, results, command, folder + "/"), images, summaries);
    }
    if (g_signals > 0 && stop_signal == 0) stop_signal = g_first_signal;  // came after the last run ended
    nlohmann::json summary = {{"tool", "valerant_eval"}, {"runs", runs.size()}, {"out", out}};
    int failed = 0;
    for (const auto& r : results) failed += !r.ok;
    summary["failed"] = failed;
    if (stop_signal) summary["stopped_by"] = signalName(stop_signal);
    // A mean that no run records (-1) is null.
    auto figure = [](double v) { return v < 0 ? nlohmann::json() : nlohmann::json(v); };
    for (const auto& s : summaries)
      summary["configs"][s.config] = {{"observed_percent", figure(s.observed_percent)},
                                      {"penetrations", figure(s.penetrations)}, {"rewinds", figure(s.rewinds)}};
    summary["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << summary.dump() << std::endl;
    if (stop_signal) return 128 + stop_signal;
    return failed ? 1 : 0;
  });
}
