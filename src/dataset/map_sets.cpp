#include "valerant/dataset/map_sets.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <set>

#include "valerant/common/error.h"
#include "valerant/config/package_dir.h"

namespace valerant::dataset {

std::vector<std::string> MapSets::heldOut() const {
  std::vector<std::string> out = evaluation;
  out.insert(out.end(), held_out_variants.begin(), held_out_variants.end());
  return out;
}

bool MapSets::isHeldOut(const std::string& map) const {
  const auto held = heldOut();
  return std::find(held.begin(), held.end(), map) != held.end();
}

MapSets loadMapSets(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw InputError(path, std::string("cannot read map sets: ") + e.what());
  }
  auto list = [&](const char* key) {
    const YAML::Node node = root[key];
    if (!node || !node.IsSequence()) throw InputError(path + ": " + key, "missing or not a list of map names");
    std::vector<std::string> names;
    for (const auto& n : node) names.push_back(n.as<std::string>());
    return names;
  };
  MapSets sets{list("tuning"), list("evaluation"), list("held_out_variants")};
  std::set<std::string> seen;
  for (const auto* l : {&sets.tuning, &sets.evaluation, &sets.held_out_variants})
    for (const auto& name : *l)
      if (!seen.insert(name).second) throw InputError(path + ": " + name, "listed twice (the lists must be disjoint)");
  return sets;
}

std::string defaultMapSetsPath() { return packageFilePath("config/map_sets.yaml"); }

}  // namespace valerant::dataset
