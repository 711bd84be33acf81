#include "valerant/slam/slam.h"

namespace valerant {

const char* toString(TrackingState state) {
  switch (state) {
    case TrackingState::kInitializing: return "initializing";
    case TrackingState::kTracking: return "tracking";
    case TrackingState::kLost: return "lost";
  }
  return "unknown";
}

}  // namespace valerant
