#pragma once
// Where the world model's warps sample (anchor_warp.h, pose_warp.h): each pixel's
// position in another frame, and bilinear sampling at such positions in pixel-index
// coordinates (pixel i's centre at i), the same arithmetic as
// learn/valerant_learn/bilinear.py. Written out rather than left to cv::remap, whose
// interpolation weights are quantised to 1/32 of a pixel: coordinates composed over a
// hundred frames would drift.
#include <opencv2/core.hpp>

namespace valerant {

struct WarpSampling {
  cv::Mat positions;  // CV_32FC2 (x, y), pixel-index coordinates of the frame sampled
  cv::Mat in_view;    // CV_32F: 1 where the pixel's ray or point lies in that frame's view
};

// `image` (CV_32F with 1, 2 or 3 channels) sampled bilinearly at `positions` (CV_32FC2):
// with `zeros_outside` false the coordinates are clamped to the image (the border
// replicated), else a tap outside the image counts 0 (torch grid_sample's "border" and
// "zeros" padding with align_corners=True).
cv::Mat sampleBilinear(const cv::Mat& image, const cv::Mat& positions, bool zeros_outside);

}  // namespace valerant
