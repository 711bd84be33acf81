#pragma once
// The life of a run directory (valerant_explore, the explorer node). A run is complete
// when its report.json, written last and atomically, parses as a report; a folder with
// run files but no such report is an unfinished run (killed, or failed), whose map of
// the committed steps lies in its snapshot/ (run_map.h saveRunSnapshot). Before any
// work, a tool states how it starts:
//   kNew     the folder holds no run (else an error naming it, saying what is there);
//   kForce   an earlier run's files are removed first (only files a run writes);
//   kResume  the folder must hold an unfinished run; the episode is run again from its
//            own config.yaml and must make the recorded decisions (episode state is not
//            serialised, so continuing means replaying: the engine world and the SLAM are
//            deterministic for a seed), then goes on and appends.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace valerant {

enum class RunState { kNone, kUnfinished, kComplete };
enum class RunStart { kNew, kForce, kResume };

RunState runState(const std::string& dir);

// Checks (and for kForce clears) `dir` for a run starting as `start`; creates it.
// Throws InputError naming `dir` when the folder does not allow that start.
void prepareRunDirectory(const std::string& dir, RunStart start);

// The names of the files and folders a run writes into its directory.
std::vector<std::string> runFileNames();

// The whole lines of `dir`/decisions.jsonl (a line cut by a kill is dropped, and the
// file is cut back to its last whole line so that appends continue it cleanly).
std::vector<nlohmann::json> recordedDecisions(const std::string& dir);

// Throws InputError when the replayed decision `replayed` differs from `recorded` in
// what was decided (step, chosen candidate, stall, rewind); timings may differ.
void requireSameDecision(const std::string& dir, const nlohmann::json& recorded, const nlohmann::json& replayed);

}  // namespace valerant
