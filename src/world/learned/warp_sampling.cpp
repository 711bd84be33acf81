#include "valerant/world/learned/warp_sampling.h"

#include <algorithm>
#include <cmath>

namespace valerant {

cv::Mat sampleBilinear(const cv::Mat& image, const cv::Mat& positions, bool zeros_outside) {
  CV_Assert(image.depth() == CV_32F && image.channels() <= 3 && positions.type() == CV_32FC2);
  const int w = image.cols, h = image.rows, channels = image.channels();
  cv::Mat out(positions.size(), image.type());
  for (int py = 0; py < positions.rows; ++py) {
    const cv::Vec2f* pos = positions.ptr<cv::Vec2f>(py);
    float* o = out.ptr<float>(py);
    for (int px = 0; px < positions.cols; ++px) {
      float x = pos[px][0], y = pos[px][1];
      if (!zeros_outside) {
        x = std::clamp(x, 0.f, static_cast<float>(w - 1));
        y = std::clamp(y, 0.f, static_cast<float>(h - 1));
      }
      const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
      const float fx = x - x0, fy = y - y0;
      const int xs[2] = {x0, x0 + 1}, ys[2] = {y0, y0 + 1};
      const float wx[2] = {1 - fx, fx}, wy[2] = {1 - fy, fy};
      float sum[3] = {0, 0, 0};
      for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
          const float weight = wx[i] * wy[j];
          // A zero weight never reads: clamped positions on the last row or column touch
          // one pixel past it.
          if (weight == 0.f || xs[i] < 0 || xs[i] >= w || ys[j] < 0 || ys[j] >= h) continue;
          const float* src = image.ptr<float>(ys[j]) + xs[i] * channels;
          for (int c = 0; c < channels; ++c) sum[c] += weight * src[c];
        }
      for (int c = 0; c < channels; ++c) o[px * channels + c] = sum[c];
    }
  }
  return out;
}

}  // namespace valerant
