#include "valerant/world/learned/anchor_warp.h"

#include <algorithm>
#include <cmath>

namespace valerant {

RotationSampling rotationSampling(const MotionStep& motion, const CameraIntrinsics& camera) {
  const int w = camera.width, h = camera.height;
  const double a = motion.yaw_deg * M_PI / 180.0, b = motion.pitch_deg * M_PI / 180.0;
  RotationSampling r{cv::Mat(h, w, CV_32FC2), cv::Mat(h, w, CV_32F)};
  for (int py = 0; py < h; ++py) {
    cv::Vec2f* pos = r.positions.ptr<cv::Vec2f>(py);
    float* in = r.in_view.ptr<float>(py);
    const double y = (py + 0.5 - camera.cy) / camera.fy;
    const double y1 = y * std::cos(b) + std::sin(b), z1 = -y * std::sin(b) + std::cos(b);
    for (int px = 0; px < w; ++px) {
      const double x = (px + 0.5 - camera.cx) / camera.fx;
      const double x2 = x * std::cos(a) - z1 * std::sin(a), z2 = x * std::sin(a) + z1 * std::cos(a);
      if (!(z2 > 1e-6)) {
        pos[px] = cv::Vec2f(0.5f * (w - 1), 0.5f * (h - 1));
        in[px] = 0.f;
        continue;
      }
      const double u = camera.fx * x2 / z2 + camera.cx - 0.5, v = camera.fy * y1 / z2 + camera.cy - 0.5;
      pos[px] = cv::Vec2f(static_cast<float>(u), static_cast<float>(v));
      in[px] = (u >= 0 && u <= w - 1 && v >= 0 && v <= h - 1) ? 1.f : 0.f;
    }
  }
  return r;
}

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

AnchorState AnchorState::start(const cv::Mat& frame_rgb8) {
  CV_Assert(frame_rgb8.type() == CV_8UC3);
  AnchorState s;
  frame_rgb8.convertTo(s.anchor, CV_32FC3, 1.0 / 255.0);
  s.coords.create(frame_rgb8.size(), CV_32FC2);
  for (int y = 0; y < frame_rgb8.rows; ++y)
    for (int x = 0; x < frame_rgb8.cols; ++x) s.coords.at<cv::Vec2f>(y, x) = cv::Vec2f(x, y);
  s.valid = cv::Mat(frame_rgb8.size(), CV_32F, cv::Scalar(1));
  return s;
}

cv::Mat anchorStep(AnchorState& state, const cv::Mat& newest_rgb8, const cv::Mat& positions, const cv::Mat& mask,
                   const cv::Mat& fill) {
  CV_Assert(newest_rgb8.type() == CV_8UC3 && positions.type() == CV_32FC2 && mask.type() == CV_32F &&
            fill.type() == CV_32FC3);
  const cv::Size size = newest_rgb8.size();
  CV_Assert(positions.size() == size && mask.size() == size && fill.size() == size && state.anchor.size() == size);
  cv::Mat newest;
  newest_rgb8.convertTo(newest, CV_32FC3, 1.0 / 255.0);
  const cv::Mat coords = sampleBilinear(state.coords, positions, false);
  const cv::Mat sampled_valid = sampleBilinear(state.valid, positions, true);
  const cv::Mat from_anchor = sampleBilinear(state.anchor, coords, false);
  const cv::Mat from_newest = sampleBilinear(newest, positions, false);
  cv::Mat next(size, CV_8UC3), valid(size, CV_32F);
  int valid_count = 0;
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      const bool anchored = sampled_valid.at<float>(y, x) >= kValidMin;
      const cv::Vec3f warped = anchored ? from_anchor.at<cv::Vec3f>(y, x) : from_newest.at<cv::Vec3f>(y, x);
      const float m = mask.at<float>(y, x);
      const cv::Vec3f blended = m * warped + (1 - m) * fill.at<cv::Vec3f>(y, x);
      for (int c = 0; c < 3; ++c) next.at<cv::Vec3b>(y, x)[c] = cv::saturate_cast<uchar>(255.f * blended[c]);
      const bool stays = anchored && m >= 0.5f;
      valid.at<float>(y, x) = stays ? 1.f : 0.f;
      valid_count += stays;
    }
  if (valid_count < kReanchorFraction * size.area()) {
    state = AnchorState::start(next);
  } else {
    state.coords = coords;
    state.valid = valid;
  }
  return next;
}

}  // namespace valerant
