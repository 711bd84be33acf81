#pragma once
// How alike two 8-bit RGB images are, as video prediction papers report it: PSNR over
// every channel, and SSIM (Wang, Bovik, Sheikh and Simoncelli 2004) with their
// reference settings: an 11 x 11 Gaussian window of sigma 1.5, C1 = (0.01 L)^2,
// C2 = (0.03 L)^2 with L = 255, the weighted moments of each window, the mean over the
// windows that lie wholly inside the image (their MATLAB code's 'valid' filtering).
// SSIM is computed on each of R, G and B and the three are averaged.
#include <opencv2/core.hpp>

namespace valerant {

// PSNR in dB over every pixel and channel, peak 255: 10 log10(255^2 / MSE). Identical
// images give kMaxPsnrDb, so means over many frames stay finite. Throws InputError for
// images that are not both CV_8UC3 of one non-empty size.
constexpr double kMaxPsnrDb = 100.0;
double psnrDb(const cv::Mat& a, const cv::Mat& b);

// Mean SSIM of the R, G and B planes, in [-1, 1] (1: identical). Throws InputError for
// images that are not both CV_8UC3 of one size, at least 11 x 11.
double ssim(const cv::Mat& a, const cv::Mat& b);

}  // namespace valerant
