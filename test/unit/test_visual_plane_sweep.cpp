// Plane-sweep depth on synthetic textured walls: accurate where confident, and the
// 4.0 confidence cut drops an untextured wall.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "test_visual_scene.h"
#include "valerant/common/error.h"
#include "valerant/slam/visual/pinhole.h"
#include "valerant/slam/visual/plane_sweep.h"

using namespace valerant;
using namespace valerant::visual;

namespace {

cv::Mat prepared(const cv::Mat& rgb, const PlaneSweepParams& params) {
  cv::Mat grey;
  cv::cvtColor(rgb, grey, cv::COLOR_RGB2GRAY);
  return sweepImage(grey, params);
}

struct SweepCase {
  SweepDepth depth;
  cv::Mat truth;  // at sweep resolution
};

// A camera 5 m from a textured far wall (z = 5) whose left wall (x = -2) is blank.
SweepCase sweepRoom(bool simd = true) {
  const test::BoxRoom room({-2, -1.5, -3}, {3, 1.5, 5}, /*blank_wall=*/0);
  const CameraIntrinsics k = test::BoxRoom::camera();
  PlaneSweepParams params;
  params.simd = simd;
  const CameraIntrinsics ks = downsampled(k, params.downsample);
  const Eigen::Isometry3d ref = test::BoxRoom::pose({0, 0, 0}, 0);
  const auto view = room.render(k, ref);
  std::vector<SweepView> sources;
  for (const Eigen::Vector3d& c : {Eigen::Vector3d(-0.3, 0, -0.4), Eigen::Vector3d(0.25, 0.05, -0.2)}) {
    const Eigen::Isometry3d pose = test::BoxRoom::pose(c, 3);
    sources.push_back({prepared(room.render(k, pose).rgb, params), pose});
  }
  SweepCase out;
  out.depth = planeSweep({prepared(view.rgb, params), ref}, sources, ks, 0.8, params);
  cv::resize(view.depth, out.truth, cv::Size(ks.width, ks.height), 0, 0, cv::INTER_AREA);
  return out;
}

}  // namespace

TEST(VisualPlaneSweep, ConfidentDepthIsAccurate) {
  const SweepCase c = sweepRoom();
  int confident = 0, textured = 0;
  double abs_rel = 0;
  for (int y = 0; y < c.truth.rows; ++y) {
    for (int x = 0; x < c.truth.cols; ++x) {
      const bool on_blank_wall = x < c.truth.cols * 0.25 && std::abs(c.truth.at<float>(y, x) - 5.f) > 0.2f &&
                                 std::abs(y - c.truth.rows / 2) < c.truth.rows / 4;
      if (on_blank_wall) continue;
      ++textured;
      if (c.depth.confidence.at<float>(y, x) < 4.0f) continue;
      ++confident;
      abs_rel += std::abs(c.depth.depth.at<float>(y, x) - c.truth.at<float>(y, x)) / c.truth.at<float>(y, x);
    }
  }
  ASSERT_GT(confident, 0);
  EXPECT_LT(abs_rel / confident, 0.03);
  EXPECT_GT(static_cast<double>(confident) / textured, 0.6);
}

TEST(VisualPlaneSweep, EveryInstructionSetGivesTheSameBits) {
  if (fastestSweepIsa() == SweepIsa::kPortable) GTEST_SKIP() << "only the portable path on this CPU";
  const SweepCase portable = sweepRoom(false), fast = sweepRoom(true);
  for (const auto& [a, b] : {std::pair{portable.depth.depth, fast.depth.depth},
                             std::pair{portable.depth.confidence, fast.depth.confidence}}) {
    ASSERT_EQ(a.size(), b.size());
    EXPECT_TRUE(std::equal(a.datastart, a.dataend, b.datastart));  // NaN by its bits
  }
}

TEST(VisualPlaneSweep, BlankWallIsNotConfident) {
  const SweepCase c = sweepRoom();
  // The blank wall x = -2 fills the left edge of the view, 2 m to the side.
  int blank = 0, confident = 0;
  for (int y = c.truth.rows / 3; y < 2 * c.truth.rows / 3; ++y) {
    for (int x = 2; x < 12; ++x) {
      ++blank;
      confident += c.depth.confidence.at<float>(y, x) >= 4.0f;
    }
  }
  EXPECT_LT(static_cast<double>(confident) / blank, 0.05);
}

TEST(VisualPlaneSweep, NeedsASource) {
  const PlaneSweepParams params;
  const CameraIntrinsics k = downsampled(test::BoxRoom::camera(), params.downsample);
  EXPECT_THROW(planeSweep({cv::Mat(k.height, k.width, CV_32F, cv::Scalar(0)), {}}, {}, k, 1.0, params), InputError);
}

// With near = 0.05 m there are at most 64 planes, so a plane step of at least
// (1 / 0.05) / 63 = 0.317 per metre: the far wall at 5 m (inverse depth 0.2) sits below
// plane 0.63 and cannot get its true depth, and nothing beyond 1 / (1.5 * 0.317) = 2.1 m
// may get one (before, the plane at index 1 +- 0.5 reached 6.3 m).
TEST(VisualPlaneSweep, DepthsNearInfinityAreUnknown) {
  const test::BoxRoom room({-2, -1.5, -3}, {3, 1.5, 5});
  const CameraIntrinsics k = test::BoxRoom::camera();
  const PlaneSweepParams params;
  const Eigen::Isometry3d ref = test::BoxRoom::pose({0, 0, 0}, 0), src = test::BoxRoom::pose({0.25, 0.05, -0.2}, 3);
  const SweepDepth d = planeSweep({prepared(room.render(k, ref).rgb, params), ref},
                                  {{prepared(room.render(k, src).rgb, params), src}},
                                  downsampled(k, params.downsample), 0.05, params);
  const float bound = 63 * 0.05f / 1.5f;
  int finite = 0;
  for (int y = 0; y < d.depth.rows; ++y)
    for (int x = 0; x < d.depth.cols; ++x) {
      const float z = d.depth.at<float>(y, x);
      if (!std::isfinite(z)) continue;
      ++finite;
      EXPECT_LE(z, bound + 1e-3f);
    }
  EXPECT_GT(finite, 0);  // the side walls and floor near the camera still get depth
}
