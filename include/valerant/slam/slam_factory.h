#pragma once
// Builds a SLAM backend by name ("visual" or "oracle"); InputError for anything else.
#include <memory>
#include <string>

#include "valerant/config/config.h"
#include "valerant/slam/slam.h"

namespace valerant {

std::unique_ptr<Slam> makeSlam(const std::string& backend, const CameraIntrinsics& intrinsics, const Config& config);

}  // namespace valerant
