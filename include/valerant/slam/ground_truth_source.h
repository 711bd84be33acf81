#pragma once
// Where the oracle SLAM (oracle_slam.h) reads the truth of the frames it tracks. A real
// SLAM sees images and their stamps only (SlamInput); the oracle is an instrument of
// evaluation and asks this source for the frame a stamp names. Whoever feeds the oracle
// frames provides the source (rollout_truth.h adapts the world's rollouts).
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <optional>

#include "valerant/slam/slam.h"

namespace valerant {

// The true view of one frame.
struct TrueView {
  Eigen::Isometry3d camera_to_world;  // optical frame in the world frame, world units
  cv::Mat depth_m;                    // CV_32F metres along the optical axis, NaN = unknown
};

class GroundTruthSource {
 public:
  virtual ~GroundTruthSource() = default;
  // The true view of the frame `stamp` names; nullopt when the source has none.
  // Called from the threads of every branch at once.
  virtual std::optional<TrueView> viewOf(const FrameStamp& stamp) const = 0;
};

}  // namespace valerant
