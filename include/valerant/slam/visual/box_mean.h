#pragma once
// The plane sweep's window sum: the mean of each pixel's window x window box of a float
// image, borders replicated. OpenCV's cv::boxFilter (CV_32F, normalised,
// BORDER_REPLICATE) took a quarter of a sweep; this computes the same numbers in the
// same order, for the windows OpenCV sums directly (3 and 5):
//   row sum   r(y, x) = (double)e(y, x - h) + ... + e(y, x + h), left to right;
//   column    S = r(-h) + ... + r(h - 1) from 0, then for each row y:
//             s = S + r(y + h); out(y) = (float)(s / window^2 as one double product);
//             S = s - r(y - h),
// with h = window / 2 and e, r replicated past the borders. So the sweep's costs, and a
// run's decisions, keep their bits. Other windows go to cv::boxFilter itself.
// The AVX2 path (4 doubles a step) does the same operations; see sweep_kernels.h.
#include <opencv2/core.hpp>
#include <vector>

#include "valerant/slam/visual/sweep_kernels.h"

namespace valerant::visual {

class BoxMean {
 public:
  BoxMean(int window, SweepIsa isa = fastestSweepIsa());
  // `dst` (CV_32F, src's size) = the box mean of `src` (CV_32F, one channel, continuous).
  void apply(const cv::Mat& src, cv::Mat& dst);

 private:
  int window_;
  SweepIsa isa_;
  std::vector<float> padded_;   // one source row with its replicated border
  std::vector<double> rows_;    // every row's window sum, row-major
  std::vector<double> column_;  // S, the running column sums
};

}  // namespace valerant::visual
