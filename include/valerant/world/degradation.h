#pragma once
// WM-like image degradations for stress runs: sensor noise, blur, exposure flicker and
// frame jitter, the artefacts generated video shows. Deterministic for a given seed and
// frame key so checkpoint/restore and replays reproduce frames exactly.
#include <cstdint>
#include <opencv2/core.hpp>

#include "valerant/config/config.h"

namespace valerant {

bool degradationEnabled(const DegradationConfig& config);
// Returns a degraded copy of `rgb`; `frame_key` seeds this frame's randomness.
cv::Mat degradeFrame(const cv::Mat& rgb, const DegradationConfig& config, uint64_t frame_key);

}  // namespace valerant
