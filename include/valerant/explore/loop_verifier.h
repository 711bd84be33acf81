#pragma once
// Geometric verification of a loop candidate: does a new committed keyframe see the
// place an older one saw, and where is it relative to that one? The new keyframe's ORB
// features are matched to the old one's (Hamming, ratio test, only features with depth
// on the old keyframe), RANSAC PnP poses the new camera against the old keyframe's 3D
// points, and the scale between the two keyframes is the median ratio of the matched
// points' depths (the old points seen from the posed new camera over the new keyframe's
// own depths). The result must agree with the pose graph's prediction within limits: a
// wrong match (a similar-looking place elsewhere) would pull the map apart.
#include <string>

#include "valerant/common/camera.h"
#include "valerant/config/config.h"
#include "valerant/explore/keyframe_features.h"
#include "valerant/geometry/similarity3.h"

namespace valerant {

struct LoopVerification {
  bool accepted = false;
  // Why not, when not accepted: few_matches, few_inliers, no_scale (no depth on the new
  // keyframe for the scale), offset, rotation or scale (disagrees with the prediction).
  std::string reason;
  std::string detail;      // the same with the numbers
  int matches = 0;         // ratio-test matches with depth on the old keyframe
  int inliers = 0;         // RANSAC PnP inliers
  Similarity3 relative;           // measured: new camera to old camera (S_old^-1 S_new)
  double offset_eye_heights = 0;  // against the prediction: centre offset, ...
  double rotation_deg = 0;        // ... rotation, ...
  double scale_ratio = 1;         // ... measured over predicted scale
};

// `predicted`: S_old^-1 S_new from the pose graph; `eye_height`: one eye height in the
// old keyframe's camera units; `estimate_scale`: false for a metric SLAM (scale 1).
LoopVerification verifyLoop(const KeyframeFeatures& old_keyframe, const KeyframeFeatures& new_keyframe,
                            const Similarity3& predicted, double eye_height, bool estimate_scale, const CameraIntrinsics& k,
                            const LoopClosureConfig& config);

}  // namespace valerant
