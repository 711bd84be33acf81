#pragma once
// Everything loaded once per map and shared read-only by every world instance and
// branch: the archive file system, the parsed BSP, its triangle geometry, textures and
// the collision model.
#include <memory>
#include <string>

#include "valerant/world/quake3/bsp.h"
#include "valerant/world/quake3/collision_model.h"
#include "valerant/world/quake3/map_geometry.h"
#include "valerant/world/quake3/pk3_archive.h"
#include "valerant/world/quake3/texture_library.h"

namespace valerant::quake3 {

struct Quake3Map {
  std::unique_ptr<Pk3FileSystem> fs;
  BspMap bsp;
  MapGeometry geometry;
  std::unique_ptr<TextureLibrary> textures;
  std::unique_ptr<CollisionModel> collision;
};

// `spec` is a map name found in the installed OpenArena pk3s ("oa_dm1") or
// "/path/to/file.pk3:mapname" (that archive mounted over the installed data, which
// still provides shared textures). Throws InputError naming the map or archive.
std::shared_ptr<const Quake3Map> loadQuake3Map(const std::string& spec, int patch_level);

// Names of every map in the installed pk3s, sorted.
std::vector<std::string> installedMapNames();

}  // namespace valerant::quake3
