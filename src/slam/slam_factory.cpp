#include "valerant/slam/slam_factory.h"

#include "valerant/common/error.h"
#include "valerant/slam/depth_prior_factory.h"
#include "valerant/slam/oracle_slam.h"
#include "valerant/slam/visual/visual_slam.h"

namespace valerant {

std::unique_ptr<Slam> makeSlam(const std::string& backend, const CameraIntrinsics& intrinsics, const Config& config,
                               std::shared_ptr<const GroundTruthSource> truth) {
  if (backend == "oracle") return std::make_unique<OracleSlam>(intrinsics, config.slam, std::move(truth));
  if (backend == "visual")
    return std::make_unique<VisualSlam>(intrinsics, config.slam, loadDepthPrior(config.slam));
  throw InputError("slam backend '" + backend + "'", "unknown (known: visual, oracle)");
}

}  // namespace valerant
