#include "valerant/world/world_factory.h"

#include "valerant/common/error.h"
#include "valerant/world/learned/learned_world.h"
#include "valerant/world/quake3/quake3_world.h"

namespace valerant {

std::unique_ptr<WorldModel> makeWorld(const Config& config, const std::string& image,
                                      std::shared_ptr<const quake3::Quake3Map>& map) {
  const std::string& backend = config.world.backend;
  if (!image.empty() && backend != "learned")
    throw InputError("screenshot " + image, "starts the learned world only (world.backend is '" + backend +
                                                "'; set world.backend=learned)");
  if (backend == "learned" && !image.empty())
    return LearnedWorld::fromScreenshot(loadWorldModelNet(config), readScreenshot(image), config);
  if (backend != "quake3" && backend != "learned")
    throw InputError("world backend '" + backend + "'",
                     "not available here (quake3 or learned; bag replays a recording in the ROS graph)");
  if (!map) map = quake3::loadQuake3Map(config.world.map, config.world.patch_level);
  if (backend == "learned") return LearnedWorld::fromSpawn(loadWorldModelNet(config), map, config);
  return std::make_unique<quake3::Quake3World>(map, config);
}

}  // namespace valerant
