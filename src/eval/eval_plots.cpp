#include "valerant/eval/eval_plots.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "valerant/common/error.h"
#include "valerant/common/output_file.h"
#include "valerant/config/package_dir.h"

extern char** environ;

namespace valerant {
namespace {

// A figure no run records is -1 in a summary and null in the plot data.
nlohmann::json figure(double v) { return v < 0 ? nlohmann::json() : nlohmann::json(v); }

nlohmann::json bars(const std::vector<ConfigSummary>& summaries, const std::string& name, const std::string& title,
                    const std::string& ylabel, double ConfigSummary::*value) {
  nlohmann::json values = nlohmann::json::object();
  for (const auto& s : summaries) values[s.config] = figure(s.*value);
  return {{"name", name}, {"title", title}, {"ylabel", ylabel}, {"values", values}};
}

// The last non-empty line of a file ("" when there is none).
std::string lastLine(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

// Runs `argv` with its stderr in `log` (no shell: paths stay as they are); its exit
// status, or -1 when it died of a signal.
int runLogged(const std::vector<std::string>& argv, const std::string& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int error = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) throw InputError(argv[0], std::string("cannot be started: ") + std::strerror(error));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw InputError(argv[0], "lost its process");
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

nlohmann::json evalPlotData(const std::vector<ConfigSummary>& summaries) {
  nlohmann::json configs = nlohmann::json::array(), series = nlohmann::json::object(),
                 by_wall = nlohmann::json::object(), wall = nlohmann::json::object();
  for (const auto& s : summaries) {
    configs.push_back(s.config);
    series[s.config] = s.observed_by_step;
    by_wall[s.config] = s.observed_by_committed_step;
    wall[s.config] = s.wall_seconds_by_committed_step;
  }
  nlohmann::json coverage = {{"name", "coverage_by_step"},
                             {"title", "reachable floor observed by step (mean over runs)"},
                             {"xlabel", "step"},
                             {"ylabel", "reachable floor observed (%)"},
                             {"series", series}};
  // One point per committed step: the mean wall seconds spent and the mean coverage then.
  nlohmann::json coverage_by_wall = {{"name", "coverage_by_wall_time"},
                                     {"title", "reachable floor observed against wall time (mean over runs)"},
                                     {"xlabel", "wall seconds"},
                                     {"ylabel", "reachable floor observed (%)"},
                                     {"x", wall},
                                     {"series", by_wall}};
  return {{"configs", configs},
          {"curves", nlohmann::json::array({coverage, coverage_by_wall})},
          {"bars", nlohmann::json::array(
                       {bars(summaries, "penetrations", "penetrating committed frames per run (mean)",
                             "penetrating frames per run", &ConfigSummary::penetrations),
                        bars(summaries, "coverage_per_clean_step",
                             "reachable floor observed per penetration-free step (mean)", "m² per clean step",
                             &ConfigSummary::observed_m2_per_clean_step)})}};
}

std::string plotScriptPath() { return packageFilePath("scripts/plot_eval.py"); }

void drawEvalPlots(const std::vector<ConfigSummary>& summaries, const std::string& folder, const std::string& script,
                   const std::string& python) {
  if (!std::filesystem::is_regular_file(script)) throw InputError(script, "the plotting script is missing");
  if (access(python.c_str(), X_OK) != 0)
    throw InputError(script, "needs " + python + " (Debian's python3 with python3-matplotlib), which is missing");
  const std::string data = (std::filesystem::path(folder) / "plots.json").string();
  writeFileAtomically(data, evalPlotData(summaries).dump(1) + "\n");
  const std::string log = (std::filesystem::path(folder) / "plot_eval.log").string();
  const int status = runLogged({python, script, data}, log);
  const std::string message = lastLine(log);
  if (status != 0)
    throw InputError(script, "failed (" + (status < 0 ? std::string("killed") : "exit " + std::to_string(status)) +
                                 ")" + (message.empty() ? "" : ": " + message) + " (its output: " + log + ")");
  std::filesystem::remove(log);  // kept only to say why a run failed
}

}  // namespace valerant
