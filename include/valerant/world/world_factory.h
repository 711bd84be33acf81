#pragma once
// The in-process world of config.world.backend: quake3 (the engine at world.spawn) or
// learned (world/learned/learned_world.h), started from a screenshot when `image` is
// given, else from the engine spawn with the engine as its truth shadow. The bag
// backend replays a recording inside the ROS graph (ros/bag_world.h) and is not made
// here.
#include <memory>
#include <string>

#include "valerant/config/config.h"
#include "valerant/world/quake3/quake3_map.h"
#include "valerant/world/world_model.h"

namespace valerant {

// `map`: the engine map the world runs on (or shadows), loaded here when null and
// needed, so a caller that builds the world again reuses it; it stays null for a
// screenshot start, which has no level. Throws InputError naming the backend for bag or
// an `image` with another backend than learned, and naming the file for a bad image,
// model or map.
std::unique_ptr<WorldModel> makeWorld(const Config& config, const std::string& image,
                                      std::shared_ptr<const quake3::Quake3Map>& map);

}  // namespace valerant
