#include "valerant/world/degradation.h"

#include <opencv2/imgproc.hpp>

namespace valerant {

bool degradationEnabled(const DegradationConfig& c) {
  return c.noise_sigma > 0 || c.blur_sigma > 0 || c.exposure_flicker > 0 || c.jitter_px > 0;
}

cv::Mat degradeFrame(const cv::Mat& rgb, const DegradationConfig& c, uint64_t frame_key) {
  cv::RNG rng(frame_key * 0x9E3779B97F4A7C15ull + 1);
  cv::Mat out = rgb.clone();
  if (c.jitter_px > 0) {
    const double dx = rng.uniform(-c.jitter_px, c.jitter_px), dy = rng.uniform(-c.jitter_px, c.jitter_px);
    const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, dx, 0, 1, dy);
    cv::warpAffine(out, out, shift, out.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  }
  if (c.blur_sigma > 0) cv::GaussianBlur(out, out, cv::Size(0, 0), c.blur_sigma);
  if (c.exposure_flicker > 0 || c.noise_sigma > 0) {
    cv::Mat f;
    out.convertTo(f, CV_32FC3, 1.0 + (c.exposure_flicker > 0 ? rng.uniform(-c.exposure_flicker, c.exposure_flicker) : 0.0));
    if (c.noise_sigma > 0) {
      cv::Mat noise(f.size(), CV_32FC3);
      rng.fill(noise, cv::RNG::NORMAL, 0.0, c.noise_sigma);
      f += noise;
    }
    f.convertTo(out, CV_8UC3);  // saturates to [0, 255]
  }
  return out;
}

}  // namespace valerant
