#include "valerant/slam/slam_factory.h"

#include "valerant/common/error.h"
#include "valerant/slam/oracle_slam.h"

namespace valerant {

std::unique_ptr<Slam> makeSlam(const std::string& backend, const CameraIntrinsics& intrinsics, const Config& config) {
  if (backend == "oracle") return std::make_unique<OracleSlam>(intrinsics, config.slam);
  if (backend == "visual") throw InputError("slam backend 'visual'", "is not built yet (use --slam oracle)");
  throw InputError("slam backend '" + backend + "'", "unknown (known: visual, oracle)");
}

}  // namespace valerant
