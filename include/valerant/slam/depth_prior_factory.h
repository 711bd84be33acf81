#pragma once
// Builds the depth prior that slam.depth_prior names: nullptr for "none", the ONNX
// model at slam.depth_prior_model (relative to the package folder) for "learned".
// InputError for another value or a model that does not load (depth_prior.h).
#include <memory>

#include "valerant/config/config.h"
#include "valerant/common/depth_prior.h"

namespace valerant {

std::shared_ptr<const DepthPrior> loadDepthPrior(const SlamConfig& config);

}  // namespace valerant
