#include "valerant/slam/depth_prior_factory.h"

#include "valerant/common/error.h"
#include "valerant/config/package_dir.h"

namespace valerant {

std::shared_ptr<const DepthPrior> loadDepthPrior(const SlamConfig& config) {
  if (config.depth_prior == "none") return nullptr;
  if (config.depth_prior == "learned")
    return std::make_shared<const DepthPrior>(packageFilePath(config.depth_prior_model),
                                              cv::Size(config.depth_prior_width, config.depth_prior_height));
  throw InputError("slam.depth_prior '" + config.depth_prior + "'", "unknown (known: none, learned)");
}

}  // namespace valerant
