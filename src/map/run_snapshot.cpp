#include "valerant/map/run_snapshot.h"

#include <fcntl.h>
#include <stdio.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "valerant/common/error.h"
#include "valerant/common/output_file.h"
#include "valerant/common/tum_trajectory.h"
#include "valerant/map/keyframe_points_file.h"

namespace valerant {
namespace {

namespace fs = std::filesystem;

std::string inside(const std::string& dir, const std::string& name) { return (fs::path(dir) / name).string(); }

std::string partName(unsigned n) {
  char name[32];
  std::snprintf(name, sizeof name, "keyframes.%06u.pcd", n);
  return name;
}

// Whether `part` still holds keyframes of the map, in its place.
bool holds(const std::vector<std::shared_ptr<const FusedKeyframe>>& keyframes, size_t first,
           const std::vector<uint64_t>& ids) {
  if (first + ids.size() > keyframes.size()) return false;
  for (size_t i = 0; i < ids.size(); ++i)
    if (keyframes[first + i]->id != ids[i]) return false;
  return true;
}

}  // namespace

RunSnapshot::RunSnapshot(std::string dir) : dir_(std::move(dir)) {}

void RunSnapshot::write(const RunMap& run, nlohmann::json report) {
  const std::string config_path = inside(dir_, run_files::kConfig);
  if (!fs::is_regular_file(config_path))
    throw InputError(config_path, "missing: copy the run's configuration first (saveRunConfig)");
  const std::string snapshot = runSnapshotDir(dir_);
  const std::string building = inside(dir_, ".snapshot.partial");
  fs::remove_all(building);  // a build a killed process left behind
  fs::create_directories(building);
  const auto& keyframes = run.map.keyframes();
  std::vector<Part> parts;
  try {
    std::ifstream in(config_path, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    if (!in && !in.eof()) throw InputError(config_path, "cannot read");
    writeFileAtomically(inside(building, run_files::kConfig), bytes.str());
    // The parts that still hold, linked from the snapshot on disk ...
    size_t written = 0;
    for (const Part& part : parts_) {
      if (part.first != written || !holds(keyframes, part.first, part.ids)) break;
      std::error_code error;
      fs::create_hard_link(inside(snapshot, part.file), inside(building, part.file), error);
      if (error) break;  // gone from disk, or a file system without links: written again below
      parts.push_back(part);
      written += part.ids.size();
    }
    // ... and one new part for the rest.
    if (written < keyframes.size() || parts.empty()) {
      Part part{partName(next_part_++), {}, written, 0};
      for (size_t k = written; k < keyframes.size(); ++k) part.ids.push_back(keyframes[k]->id);
      part.points = writeKeyframePoints(inside(building, part.file), keyframes, written, keyframes.size());
      parts.push_back(std::move(part));
    }
    writeKeyframePoses(inside(building, run_files::kKeyframePoses), run.map);
    writeTumTrajectory(inside(building, run_files::kTrajectory), run.trajectory);
    nlohmann::json point_files = nlohmann::json::array();
    size_t points = 0;
    for (const Part& part : parts) {
      point_files.push_back({{"file", part.file}, {"points", part.points}});
      points += part.points;
    }
    report["run_map"] = runMapReport(run, bytes.str().size(), points);
    report["run_map"]["point_files"] = point_files;
    report["snapshot"] = true;
    writeFileAtomically(inside(building, run_files::kReport), report.dump(2) + '\n');
  } catch (...) {
    std::error_code ignored;  // the failure itself is what the caller hears about
    fs::remove_all(building, ignored);
    throw;
  }
  // Swap the new snapshot in: one rename, whether or not an old one is there.
  if (fs::exists(snapshot)) {
    if (::renameat2(AT_FDCWD, building.c_str(), AT_FDCWD, snapshot.c_str(), RENAME_EXCHANGE) != 0)
      throw InputError(snapshot, std::string("cannot swap in the new snapshot: ") + std::strerror(errno));
    fs::remove_all(building);  // now the old snapshot; the parts kept live on as links
  } else if (::rename(building.c_str(), snapshot.c_str()) != 0) {
    throw InputError(snapshot, std::string("cannot move the snapshot into place: ") + std::strerror(errno));
  }
  parts_ = std::move(parts);
}

}  // namespace valerant
