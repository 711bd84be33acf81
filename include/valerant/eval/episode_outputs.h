#pragma once
// Everything an episode leaves in its output directory, written by this one function
// for valerant_explore and for the explorer node alike: every export format
// (map/run_exports.h: map.ply, map.pcd, map.bt, grid.pgm + grid.yaml, mesh.obj,
// mesh.glb, walkable.json, overview.png, orbit.png), the map kept for valerant_export
// (map/run_map.h: keyframes.pcd, keyframes.txt; config.yaml must be saved first with
// saveRunConfig), trajectory.txt (TUM, SLAM frame), gt_trajectory.txt (TUM, BSP frame,
// game units; only with ground truth), topdown.png, view.png (the last committed frame) and, last,
// report.json (with the ground-truth figures when the engine map is given): its
// presence marks the run complete (run_directory.h). decisions.jsonl is the caller's,
// written step by step. Every file is written atomically (common/output_file.h).
#include <nlohmann/json.hpp>
#include <string>

#include "valerant/eval/snapshot_schedule.h"
#include "valerant/map/run_snapshot.h"
#include "valerant/explore/episode.h"
#include "valerant/world/quake3/quake3_map.h"

namespace valerant {

// The fields every run's report.json starts with: the tool that ran it and the run's
// world backend, map, spawn, SLAM, policy, seed, budget and switches.
nlohmann::json runReportHeader(const std::string& tool, const Config& config);

// After a step that changed the map (a commit or a rewind), the map of the committed
// steps into the run's snapshot (run_snapshot.h), its report made of `header` and the
// step counts, when `schedule` says one is due (snapshot_schedule.h). Returns the
// seconds spent writing (0 when none was written).
double snapshotAfterStep(RunSnapshot& snapshot, const Episode& episode, const StepRecord& step,
                         const nlohmann::json& header, SnapshotSchedule& schedule);

// Writes every output but report.json and adds files, statistics, ground truth and
// output_stage_seconds (the seconds of each part; the exports run beside the rest) to
// `report`. `map`: the engine map the episode ran on, or that shadowed the learned world
// (null: no ground truth; report.json's ground_truth is null, and so is frames_rendered
// and there is no gt_trajectory.txt when the frames came without truth).
void writeEpisodeOutputs(const Episode& episode, const quake3::Quake3Map* map, const std::string& out, bool overwrite,
                         nlohmann::json& report);
// Writes `report` as `out`/report.json, the run's last file, and then removes the
// snapshot of its committed steps, which the final files supersede.
void writeRunReport(const std::string& out, const nlohmann::json& report);

}  // namespace valerant
