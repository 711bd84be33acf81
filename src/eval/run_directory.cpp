#include "valerant/eval/run_directory.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "valerant/common/error.h"
#include "valerant/map/run_exports.h"
#include "valerant/map/run_map.h"

namespace valerant {
namespace {

namespace fs = std::filesystem;

// The fields of a decision that a replay must reproduce exactly.
const char* const kDecisionFields[] = {"step", "checkpoint", "chosen", "stall", "rewind", "rewind_to"};

bool isTemporary(const std::string& name) {
  return name.rfind(".", 0) == 0 && name.find(".partial") != std::string::npos;
}

// What a killed writer left: temporary files of atomic writes, a snapshot being built.
void removeTemporaryFiles(const std::string& dir) {
  for (const auto& entry : fs::directory_iterator(dir))
    if (isTemporary(entry.path().filename().string())) fs::remove_all(entry.path());
}

bool isRunFile(const std::string& name) {
  for (const auto& n : runFileNames())
    if (n == name) return true;
  return isTemporary(name);
}

std::string describeState(RunState state) {
  return state == RunState::kComplete ? "holds a finished run" : "holds an unfinished run (no complete report.json)";
}

}  // namespace

std::vector<std::string> runFileNames() {
  std::vector<std::string> names = exportFiles(exportFormats());
  for (const char* n : {run_files::kKeyframePoints, run_files::kKeyframePoses, run_files::kConfig,
                        run_files::kTrajectory, "gt_trajectory.txt", "topdown.png", "view.png", "decisions.jsonl",
                        run_files::kReport, "snapshot"})
    names.push_back(n);
  return names;
}

RunState runState(const std::string& dir) {
  if (!fs::is_directory(dir)) return RunState::kNone;
  const fs::path report = fs::path(dir) / run_files::kReport;
  if (fs::is_regular_file(report)) {
    std::ifstream in(report);
    try {
      const nlohmann::json j = nlohmann::json::parse(in);
      if (j.is_object() && j.contains("tool")) return RunState::kComplete;
    } catch (const nlohmann::json::exception&) {
    }
  }
  for (const auto& entry : fs::directory_iterator(dir))
    if (isRunFile(entry.path().filename().string())) return RunState::kUnfinished;
  return RunState::kNone;
}

void prepareRunDirectory(const std::string& dir, RunStart start) {
  const RunState state = runState(dir);
  switch (start) {
    case RunStart::kNew:
      if (state == RunState::kComplete) throw InputError(dir, describeState(state) + " already (pass --force to replace it)");
      if (state == RunState::kUnfinished)
        throw InputError(dir, describeState(state) +
                                  ": pass --resume to continue it or --force to replace it (the map of its committed "
                                  "steps is in " + dir + "/snapshot)");
      break;
    case RunStart::kResume:
      if (state != RunState::kUnfinished)
        throw InputError(dir, state == RunState::kComplete ? "holds a finished run: nothing to resume"
                                                           : "holds no run to resume");
      if (!fs::is_regular_file(fs::path(dir) / run_files::kConfig))
        throw InputError(dir + "/" + run_files::kConfig, "missing: the unfinished run cannot be resumed (pass --force)");
      removeTemporaryFiles(dir);
      break;
    case RunStart::kForce:
      if (fs::is_directory(dir))
        for (const auto& entry : fs::directory_iterator(dir))
          if (isRunFile(entry.path().filename().string())) fs::remove_all(entry.path());
      break;
  }
  std::error_code error;
  fs::create_directories(dir, error);
  if (error || !fs::is_directory(dir)) throw InputError(dir, "cannot create the run directory: " + error.message());
}

std::vector<nlohmann::json> recordedDecisions(const std::string& dir) {
  const std::string path = (fs::path(dir) / "decisions.jsonl").string();
  std::vector<nlohmann::json> decisions;
  if (!fs::exists(path)) return decisions;
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  const std::string all = text.str();
  const size_t whole = all.rfind('\n') == std::string::npos ? 0 : all.rfind('\n') + 1;
  std::stringstream lines(all.substr(0, whole));
  int number = 0;
  for (std::string line; std::getline(lines, line);) {
    ++number;
    try {
      decisions.push_back(nlohmann::json::parse(line));
    } catch (const nlohmann::json::exception& e) {
      throw InputError(path + ":" + std::to_string(number), std::string("not a decision: ") + e.what());
    }
  }
  if (whole < all.size() && ::truncate(path.c_str(), static_cast<off_t>(whole)) != 0)
    throw InputError(path, "cannot cut the line a kill left unfinished");
  return decisions;
}

void requireSameDecision(const std::string& dir, const nlohmann::json& recorded, const nlohmann::json& replayed) {
  for (const char* field : kDecisionFields) {
    const auto a = recorded.find(field), b = replayed.find(field);
    const bool same = (a == recorded.end()) == (b == replayed.end()) && (a == recorded.end() || *a == *b);
    if (!same)
      throw InputError(dir + "/decisions.jsonl",
                       "step " + replayed.value("step", nlohmann::json()).dump() + ": the resumed episode's " + field +
                           " is " + (b == replayed.end() ? "absent" : b->dump()) + " where the recorded run's is " +
                           (a == recorded.end() ? "absent" : a->dump()) +
                           ": the run cannot be continued (pass --force to replace it)");
  }
}

}  // namespace valerant
