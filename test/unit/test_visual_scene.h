#pragma once
// A synthetic world for the visual SLAM tests: a closed box room whose six walls carry
// smooth random textures, ray cast per pixel into RGB and ground-truth depth. The
// world frame is an optical frame (x right, y down, z forward at the start).
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "valerant/common/camera.h"

namespace valerant::test {

struct RenderedView {
  cv::Mat rgb;    // CV_8UC3
  cv::Mat depth;  // CV_32F along the optical axis
};

class BoxRoom {
 public:
  // `lo`, `hi`: opposite corners. `blank_wall` >= 0 leaves that wall untextured (0: -x,
  // 1: +x, 2: -y, 3: +y, 4: -z, 5: +z).
  BoxRoom(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int blank_wall = -1, uint64_t seed = 7)
      : lo_(lo), hi_(hi) {
    cv::RNG rng(seed);
    for (int w = 0; w < 6; ++w) textures_[w] = makeTexture(rng, w == blank_wall);
  }

  static CameraIntrinsics camera(int width = 320, int height = 240) {
    return CameraIntrinsics::fromHorizontalFov(width, height, 90);
  }

  // Camera at `centre`, turned `yaw_deg` about the world's down axis (positive turns
  // from +z towards +x: right), looking along +z at yaw 0.
  static Eigen::Isometry3d pose(const Eigen::Vector3d& centre, double yaw_deg) {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
    t.translation() = centre;
    return t;
  }

  RenderedView render(const CameraIntrinsics& k, const Eigen::Isometry3d& camera_to_world) const {
    RenderedView v;
    v.rgb = cv::Mat(k.height, k.width, CV_8UC3);
    v.depth = cv::Mat(k.height, k.width, CV_32F);
    const Eigen::Matrix3d r = camera_to_world.linear();
    const Eigen::Vector3d o = camera_to_world.translation();
    for (int y = 0; y < k.height; ++y) {
      for (int x = 0; x < k.width; ++x) {
        const Eigen::Vector3d ray_c((x - k.cx) / k.fx, (y - k.cy) / k.fy, 1.0);
        const Eigen::Vector3d d = r * ray_c;
        double best = std::numeric_limits<double>::max();
        int wall = -1;
        for (int axis = 0; axis < 3; ++axis) {
          if (std::abs(d[axis]) < 1e-12) continue;
          const double bound = d[axis] < 0 ? lo_[axis] : hi_[axis];
          const double t = (bound - o[axis]) / d[axis];
          if (t > 0 && t < best) best = t, wall = 2 * axis + (d[axis] < 0 ? 0 : 1);
        }
        const Eigen::Vector3d p = o + best * d;
        const int axis = wall / 2;
        const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
        const float g = sample(textures_[wall], (p[ua] - lo_[ua]) / kTexel, (p[va] - lo_[va]) / kTexel);
        const cv::Vec3f tint = kTints[wall];
        v.rgb.at<cv::Vec3b>(y, x) = cv::Vec3b(cv::saturate_cast<uchar>(g * tint[0]), cv::saturate_cast<uchar>(g * tint[1]),
                                              cv::saturate_cast<uchar>(g * tint[2]));
        v.depth.at<float>(y, x) = static_cast<float>(best);  // ray_c has z = 1: t is the depth
      }
    }
    return v;
  }

 private:
  static constexpr double kTexel = 0.02;  // metres per texel
  static constexpr int kTextureSize = 1024;
  static inline const std::array<cv::Vec3f, 6> kTints = {cv::Vec3f(1.0f, 0.9f, 0.8f), cv::Vec3f(0.8f, 1.0f, 0.9f),
                                                          cv::Vec3f(0.9f, 0.9f, 1.0f), cv::Vec3f(1.0f, 1.0f, 0.8f),
                                                          cv::Vec3f(0.8f, 0.9f, 1.0f), cv::Vec3f(1.0f, 0.8f, 0.9f)};

  // Smooth noise at three scales: corners for KLT at every distance, and no aliasing
  // at the texel size used (2 cm; a pixel covers 2.5 cm at 4 m).
  static cv::Mat makeTexture(cv::RNG& rng, bool blank) {
    cv::Mat sum(kTextureSize, kTextureSize, CV_32F, cv::Scalar(0));
    if (blank) return sum + 120.f;
    for (int cell : {4, 16, 64}) {
      cv::Mat coarse(kTextureSize / cell, kTextureSize / cell, CV_32F), fine;
      rng.fill(coarse, cv::RNG::UNIFORM, -1.0, 1.0);
      cv::resize(coarse, fine, sum.size(), 0, 0, cv::INTER_CUBIC);
      sum += fine * (cell == 4 ? 0.6f : 1.0f);
    }
    cv::GaussianBlur(sum, sum, cv::Size(0, 0), 1.5);
    cv::normalize(sum, sum, 30, 230, cv::NORM_MINMAX);
    return sum;
  }

  static float sample(const cv::Mat& tex, double u, double v) {
    u = std::clamp(u, 0.0, kTextureSize - 1.001);
    v = std::clamp(v, 0.0, kTextureSize - 1.001);
    const int x = static_cast<int>(u), y = static_cast<int>(v);
    const float a = static_cast<float>(u - x), b = static_cast<float>(v - y);
    return (1 - a) * (1 - b) * tex.at<float>(y, x) + a * (1 - b) * tex.at<float>(y, x + 1) +
           (1 - a) * b * tex.at<float>(y + 1, x) + a * b * tex.at<float>(y + 1, x + 1);
  }

  Eigen::Vector3d lo_, hi_;
  std::array<cv::Mat, 6> textures_;
};

}  // namespace valerant::test
