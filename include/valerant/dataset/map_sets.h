#pragma once
// The fixed map lists of config/map_sets.yaml: tuning maps, evaluation maps, and the
// remakes of evaluation maps that are held out with them.
#include <string>
#include <vector>

namespace valerant::dataset {

struct MapSets {
  std::vector<std::string> tuning, evaluation, held_out_variants;
  // Evaluation maps and their variants: what no training shard may hold.
  std::vector<std::string> heldOut() const;
  bool isHeldOut(const std::string& map) const;
};

// Throws InputError naming the file and key for a missing list, a repeated map, or a
// map in both tuning and held-out lists.
MapSets loadMapSets(const std::string& path);
// config/map_sets.yaml of the package folder (package_dir.h).
std::string defaultMapSetsPath();

}  // namespace valerant::dataset
