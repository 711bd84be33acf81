#include "valerant/world/quake3/quake3_map.h"

#include <filesystem>

#include "valerant/common/error.h"

namespace valerant::quake3 {

std::shared_ptr<const Quake3Map> loadQuake3Map(const std::string& spec, int patch_level) {
  auto map = std::make_shared<Quake3Map>();
  map->fs = std::make_unique<Pk3FileSystem>();
  std::string name = spec;
  const size_t colon = spec.rfind(':');
  if (colon != std::string::npos && spec.find(".pk3") != std::string::npos) {
    const std::string archive = spec.substr(0, colon);
    name = spec.substr(colon + 1);
    if (!std::filesystem::is_regular_file(archive)) throw InputError(archive, "no such pk3 archive");
    try {
      map->fs->mountDirectory(Pk3FileSystem::defaultDataDir());
    } catch (const InputError&) {
      // A standalone pk3 still loads; its textures may then fall back to placeholders.
    }
    map->fs->mountArchive(archive);
  } else {
    map->fs->mountDirectory(Pk3FileSystem::defaultDataDir());
  }
  if (name.empty()) throw InputError(spec, "no map name after the archive path");

  const std::string path = "maps/" + name + ".bsp";
  const auto bytes = map->fs->read(path);
  if (!bytes) {
    std::string hint;
    const auto all = map->fs->list("maps/", ".bsp");
    for (size_t i = 0; i < all.size() && i < 8; ++i) hint += (i ? ", " : "") + all[i].substr(5, all[i].size() - 9);
    throw InputError("map '" + name + "'", "not found in the mounted pk3s (" +
                                               std::to_string(all.size()) + " maps, e.g. " + hint + ")");
  }
  map->bsp = parseBsp(*bytes, map->fs->archiveOf(path) + ":" + path);
  map->bsp.name = name;
  map->geometry = buildMapGeometry(map->bsp, patch_level);
  map->textures = std::make_unique<TextureLibrary>(*map->fs);
  map->collision = std::make_unique<CollisionModel>(CollisionModel::fromBsp(map->bsp));
  return map;
}

std::vector<std::string> installedMapNames() {
  Pk3FileSystem fs;
  fs.mountDirectory(Pk3FileSystem::defaultDataDir());
  std::vector<std::string> names;
  for (const auto& p : fs.list("maps/", ".bsp")) names.push_back(p.substr(5, p.size() - 9));
  return names;
}

}  // namespace valerant::quake3
