#include "valerant/eval/image_similarity.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "valerant/common/error.h"

namespace valerant {
namespace {

constexpr int kWindow = 11;
constexpr double kSigma = 1.5;
constexpr double kPeak = 255.0;
constexpr double kC1 = (0.01 * kPeak) * (0.01 * kPeak);
constexpr double kC2 = (0.03 * kPeak) * (0.03 * kPeak);

std::string describe(const cv::Mat& m) {
  return std::to_string(m.cols) + "x" + std::to_string(m.rows) + " " + cv::typeToString(m.type());
}

void requireComparable(const cv::Mat& a, const cv::Mat& b, const char* metric, int min_side) {
  if (a.empty() || a.type() != CV_8UC3 || b.type() != CV_8UC3 || a.size() != b.size() || a.cols < min_side ||
      a.rows < min_side)
    throw InputError(std::string(metric) + " images",
                     "need two CV_8UC3 images of one size, at least " + std::to_string(min_side) + "x" +
                         std::to_string(min_side) + ", got " + describe(a) + " and " + describe(b));
}

// The Gaussian-weighted mean of every window, at each window's centre pixel. Windows
// reaching past the border are filtered with a reflected border and cropped away by
// the caller.
cv::Mat windowMean(const cv::Mat& plane) {
  cv::Mat mean;
  cv::GaussianBlur(plane, mean, cv::Size(kWindow, kWindow), kSigma, kSigma, cv::BORDER_REFLECT);
  return mean;
}

double planeSsim(const cv::Mat& x, const cv::Mat& y) {
  const cv::Mat mx = windowMean(x), my = windowMean(y);
  const cv::Mat mxx = mx.mul(mx), myy = my.mul(my), mxy = mx.mul(my);
  const cv::Mat vx = windowMean(x.mul(x)) - mxx, vy = windowMean(y.mul(y)) - myy;
  const cv::Mat cxy = windowMean(x.mul(y)) - mxy;
  cv::Mat numerator = (2 * mxy + kC1).mul(2 * cxy + kC2);
  cv::Mat denominator = (mxx + myy + kC1).mul(vx + vy + kC2);
  cv::Mat map;
  cv::divide(numerator, denominator, map);
  // Only windows wholly inside the image ('valid').
  const int r = kWindow / 2;
  return cv::mean(map(cv::Rect(r, r, x.cols - 2 * r, x.rows - 2 * r)))[0];
}

}  // namespace

double psnrDb(const cv::Mat& a, const cv::Mat& b) {
  requireComparable(a, b, "PSNR", 1);
  const double squared = cv::norm(a, b, cv::NORM_L2SQR);
  const double mse = squared / static_cast<double>(a.total() * a.channels());
  if (mse == 0) return kMaxPsnrDb;
  return std::min(kMaxPsnrDb, 10.0 * std::log10(kPeak * kPeak / mse));
}

double ssim(const cv::Mat& a, const cv::Mat& b) {
  requireComparable(a, b, "SSIM", kWindow);
  cv::Mat fa, fb;
  a.convertTo(fa, CV_64F);
  b.convertTo(fb, CV_64F);
  std::vector<cv::Mat> pa, pb;
  cv::split(fa, pa);
  cv::split(fb, pb);
  double sum = 0;
  for (size_t c = 0; c < pa.size(); ++c) sum += planeSsim(pa[c], pb[c]);
  return sum / static_cast<double>(pa.size());
}

}  // namespace valerant
