// The plane sweep's inner loops (sweep_kernels.h): hand-worked cases on both paths, and
// the AVX2 path equal to the portable one bit for bit on random rows and cost curves.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <random>

#include "valerant/slam/visual/sweep_kernels.h"

using namespace valerant::visual;

namespace {

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

}  // namespace

TEST(SweepKernels, TruncatedDifferencesByHand) {
  // source(u) = u (source[i] = i), sampled at u = x + 0.5, so the value is x + 0.5.
  std::vector<float> source(12);
  for (int i = 0; i < 12; ++i) source[i] = static_cast<float>(i);
  RowSampling s;
  s.scale = 1, s.shift = 0.5f, s.max_u = 8.5f, s.truncation = 1.5f, s.implausible = 100, s.invalid = 1000;
  std::vector<float> ref = {0, 1.25f, 0, 3, 4, 300, 6, 7, 8, 9};
  // |ref - (x + 0.5)|: 0.5, 0.25, 2.5 -> capped 1.5, 0.5, 0.5, 294.5 -> implausible,
  // 0.5, 0.5; x = 8 and 9 sample u = 8.5 and 9.5, outside [0, 8.5).
  const std::vector<float> expected = {1.5f, 1.25f, 2.5f, 1.5f, 1.5f, 1001, 1.5f, 1.5f, 1001, 1001};
  for (SweepIsa isa : sweepIsasHere()) {
    std::vector<float> out(10, 1.0f);
    addTruncatedDifferences(ref.data(), source.data(), 10, s, out.data(), isa);
    EXPECT_EQ(out, expected) << "isa " << static_cast<int>(isa);
  }
}

TEST(SweepKernels, BlendByHand) {
  // Between rows 0..9 and 10..19 a quarter of the way: 2.5 more than the top row.
  std::vector<float> top(10), bottom(10);
  for (int i = 0; i < 10; ++i) top[i] = static_cast<float>(i), bottom[i] = static_cast<float>(i + 10);
  for (SweepIsa isa : sweepIsasHere()) {
    std::vector<float> out(10);
    blendRows(top.data(), bottom.data(), 0.25f, 10, out.data(), isa);
    for (int i = 0; i < 10; ++i) EXPECT_EQ(out[i], static_cast<float>(i) + 2.5f) << i;
  }
}

TEST(SweepKernels, CostCurveByHand) {
  const float inf = std::numeric_limits<float>::infinity();
  // Nine pixels (one AVX2 step and a tail), three curves over six planes, invalid at 100:
  //   a: 5 4 1 3 6 2   best plane 2 (1), neighbours 4 and 3, rival plane 5 (2)
  //   b: 2 9 9 9 1 9   best plane 4 (1), neighbours 9 and 9, rival plane 0 (2)
  //   c: all invalid   no plane scored: best 0 at infinite cost, no rival
  const float a[6] = {5, 4, 1, 3, 6, 2}, b[6] = {2, 9, 9, 9, 1, 9}, c[6] = {100, 100, 200, 100, 100, 100};
  const float* curve_of_pixel[9] = {a, b, c, a, b, c, a, b, a};
  for (SweepIsa isa : sweepIsasHere()) {
    CostCurveTracker tracker(9, isa);
    for (int plane = 0; plane < 6; ++plane) {
      float costs[9];
      for (int p = 0; p < 9; ++p) costs[p] = curve_of_pixel[p][plane];
      tracker.add(plane, costs, 100);
    }
    for (size_t p = 0; p < 9; ++p) {
      SCOPED_TRACE("pixel " + std::to_string(p) + ", isa " + std::to_string(static_cast<int>(isa)));
      if (curve_of_pixel[p] == a) {
        EXPECT_EQ(tracker.best(p), 2);
        EXPECT_EQ(tracker.bestCost(p), 1);
        EXPECT_EQ(tracker.before(p), 4);
        EXPECT_EQ(tracker.after(p), 3);
        EXPECT_EQ(tracker.rivalCost(p), 2);
      } else if (curve_of_pixel[p] == b) {
        EXPECT_EQ(tracker.best(p), 4);
        EXPECT_EQ(tracker.bestCost(p), 1);
        EXPECT_EQ(tracker.before(p), 9);
        EXPECT_EQ(tracker.after(p), 9);
        EXPECT_EQ(tracker.rivalCost(p), 2);
      } else {
        EXPECT_EQ(tracker.best(p), 0);
        EXPECT_EQ(tracker.bestCost(p), inf);
        EXPECT_EQ(tracker.rivalCost(p), inf);
      }
    }
  }
}

TEST(SweepKernels, Avx2EqualsPortableBitForBit) {
  if (fastestSweepIsa() != SweepIsa::kAvx2) GTEST_SKIP() << "this CPU has no AVX2";
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(-3, 3), scale(0.6f, 1.4f), shift(-30, 60), chance(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 150 + trial % 11, cols = n + 40;
    std::vector<float> ref(n), source(cols);
    for (float& r : ref) r = value(rng);
    // Some samples near the canvas's outside value: implausible differences.
    for (float& v : source) v = chance(rng) < 0.05f ? -1e4f : value(rng);
    RowSampling s;
    s.scale = scale(rng), s.shift = shift(rng), s.max_u = static_cast<float>(cols - 1) - 1e-3f;
    s.truncation = 1.5f, s.implausible = 100, s.invalid = 1e5f;
    std::vector<float> blend_portable(cols), blend_avx2(cols);
    const float fy = chance(rng);
    blendRows(source.data(), ref.data(), fy, n, blend_portable.data(), SweepIsa::kPortable);
    blendRows(source.data(), ref.data(), fy, n, blend_avx2.data(), SweepIsa::kAvx2);
    ASSERT_TRUE(sameBits(blend_portable, blend_avx2)) << "trial " << trial;
    std::vector<float> portable(n, 0.25f), avx2(n, 0.25f);
    addTruncatedDifferences(ref.data(), source.data(), n, s, portable.data(), SweepIsa::kPortable);
    addTruncatedDifferences(ref.data(), source.data(), n, s, avx2.data(), SweepIsa::kAvx2);
    ASSERT_TRUE(sameBits(portable, avx2)) << "trial " << trial;
  }
  const size_t pixels = 19203;  // not a multiple of 8: the tail too
  CostCurveTracker portable(pixels, SweepIsa::kPortable), avx2(pixels, SweepIsa::kAvx2);
  std::uniform_real_distribution<float> cost(0, 12);
  for (int plane = 0; plane < 64; ++plane) {
    std::vector<float> costs(pixels);
    for (float& c : costs) c = chance(rng) < 0.1f ? 5000 : cost(rng);  // some not scored (invalid 4000)
    portable.add(plane, costs.data(), 4000);
    avx2.add(plane, costs.data(), 4000);
  }
  for (size_t p = 0; p < pixels; ++p) {
    ASSERT_EQ(portable.best(p), avx2.best(p)) << p;
    for (auto f : {&CostCurveTracker::bestCost, &CostCurveTracker::rivalCost, &CostCurveTracker::before,
                   &CostCurveTracker::after}) {
      const float x = (portable.*f)(p), y = (avx2.*f)(p);
      ASSERT_EQ(std::memcmp(&x, &y, sizeof x), 0) << p;
    }
  }
}
