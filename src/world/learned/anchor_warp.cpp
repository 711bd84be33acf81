#include "valerant/world/learned/anchor_warp.h"

#include <algorithm>
#include <cmath>

namespace valerant {

WarpSampling rotationSampling(const MotionStep& motion, const CameraIntrinsics& camera) {
  const int w = camera.width, h = camera.height;
  const double a = motion.yaw_deg * M_PI / 180.0, b = motion.pitch_deg * M_PI / 180.0;
  WarpSampling r{cv::Mat(h, w, CV_32FC2), cv::Mat(h, w, CV_32F)};
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

AnchorState AnchorState::start(const cv::Mat& frame_rgb8, std::optional<PoseGeometry> geometry) {
  CV_Assert(frame_rgb8.type() == CV_8UC3);
  CV_Assert(!geometry || geometry->depth.size() == frame_rgb8.size());
  AnchorState s;
  s.geometry = std::move(geometry);
  frame_rgb8.convertTo(s.anchor, CV_32FC3, 1.0 / 255.0);
  s.coords.create(frame_rgb8.size(), CV_32FC2);
  for (int y = 0; y < frame_rgb8.rows; ++y)
    for (int x = 0; x < frame_rgb8.cols; ++x) s.coords.at<cv::Vec2f>(y, x) = cv::Vec2f(x, y);
  s.valid = cv::Mat(frame_rgb8.size(), CV_32F, cv::Scalar(1));
  return s;
}

cv::Mat anchorStep(AnchorState& state, const cv::Mat& newest_rgb8, const cv::Mat& positions, const cv::Mat& mask,
                   const cv::Mat& fill, const std::optional<PoseGeometry>& moved) {
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
    state = AnchorState::start(next, moved ? std::optional<PoseGeometry>(moved->reanchored(coords)) : std::nullopt);
  } else {
    state.coords = coords;
    state.valid = valid;
    state.geometry = moved;
  }
  return next;
}

}  // namespace valerant
