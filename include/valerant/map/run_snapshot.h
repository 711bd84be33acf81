#pragma once
// The map of a run's committed steps, kept in DIR/snapshot while the run goes on, so a
// killed run loses at most the steps since the last write. The snapshot is a small run
// directory of its own (config.yaml, keyframes.txt, trajectory.txt, report.json) that
// loadRunMap and valerant_export read; its points are in parts,
// keyframes.<n>.pcd, listed in report.json's run_map.point_files in keyframe order.
//
// Why parts: a map's keyframes are only appended, or cut back by a rewind (map_fusion.h),
// so a part once written stays true for as long as its keyframes stay in the map. Each
// write hard-links the parts that still hold and writes one new part for the rest: the
// cost of a write follows the new keyframes, not the map (a 150-step run wrote its whole
// 373 MB cloud every few steps before). A loop closure replaces keyframes by corrected
// copies with new ids, so their parts are written again.
//
// The new snapshot is built beside the old one (DIR/.snapshot.partial) and swapped in by
// one atomic rename, so a process killed at any moment leaves a whole snapshot.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "valerant/map/run_map.h"

namespace valerant {

class RunSnapshot {
 public:
  // `dir`: the run directory, which must hold config.yaml (saveRunConfig).
  explicit RunSnapshot(std::string dir);
  // Writes `run` as DIR/snapshot with `report` (its run_map added) as its report.json.
  // On failure (InputError naming the file) the old snapshot stays.
  void write(const RunMap& run, nlohmann::json report);

 private:
  struct Part {
    std::string file;               // its name in the snapshot
    std::vector<uint64_t> ids;      // its keyframes' ids, from keyframe `first` on
    size_t first = 0;
    size_t points = 0;
  };
  std::string dir_;
  std::vector<Part> parts_;  // of the snapshot on disk, in keyframe order
  unsigned next_part_ = 0;   // the number in the next new part's name
};

}  // namespace valerant
