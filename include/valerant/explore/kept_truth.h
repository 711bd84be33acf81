#pragma once
// What an episode keeps of its frames' ground truth (engine world only). Every frame
// keeps its pose and penetration flags; the depth image (320 x 240 floats, 300 KB) is
// kept only for every kCommittedDepthStride-th frame of the committed trajectory, the
// frames whose visibility map accuracy tests (map_accuracy.h), and for no candidate.
// Kept whole, the candidates' depth grew the episode by about 120 MB a step.
#include <cstddef>
#include <vector>

#include "valerant/world/world_model.h"

namespace valerant {

inline constexpr size_t kCommittedDepthStride = 8;

// `frames` without their depth images (what a candidate's record keeps).
std::vector<FrameTruth> withoutDepth(const std::vector<FrameTruth>& frames);

// Appends `frames` to the committed truth `committed`; a frame keeps its depth only
// when its index in `committed` is a multiple of kCommittedDepthStride.
void appendCommittedTruth(std::vector<FrameTruth>& committed, const std::vector<FrameTruth>& frames);

}  // namespace valerant
