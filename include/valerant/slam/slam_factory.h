#pragma once
// Builds a SLAM backend by name ("visual" or "oracle"); InputError for anything else.
// `truth` is what the oracle reads (the visual backend ignores it; null is fine there).
#include <memory>
#include <string>

#include "valerant/config/config.h"
#include "valerant/slam/ground_truth_source.h"
#include "valerant/slam/slam.h"

namespace valerant {

std::unique_ptr<Slam> makeSlam(const std::string& backend, const CameraIntrinsics& intrinsics, const Config& config,
                               std::shared_ptr<const GroundTruthSource> truth);

}  // namespace valerant
