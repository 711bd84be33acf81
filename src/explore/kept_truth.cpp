#include "valerant/explore/kept_truth.h"

namespace valerant {

std::vector<FrameTruth> withoutDepth(const std::vector<FrameTruth>& frames) {
  std::vector<FrameTruth> kept(frames);
  for (FrameTruth& f : kept) f.depth_m = cv::Mat();  // drops this copy's reference only
  return kept;
}

void appendCommittedTruth(std::vector<FrameTruth>& committed, const std::vector<FrameTruth>& frames) {
  for (const FrameTruth& f : frames) {
    committed.push_back(f);
    if ((committed.size() - 1) % kCommittedDepthStride != 0) committed.back().depth_m = cv::Mat();
  }
}

}  // namespace valerant
