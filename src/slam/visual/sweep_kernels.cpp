#include "valerant/slam/visual/sweep_kernels.h"

#include <cmath>
#include <limits>

#if defined(__x86_64__)
#include <immintrin.h>
#define VALERANT_SWEEP_AVX2 1
#endif

namespace valerant::visual {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

void portableDifferences(const float* ref, const float* source, int begin, int n, const RowSampling& s, float* out) {
  for (int x = begin; x < n; ++x) {
    const float u = s.scale * static_cast<float>(x) + s.shift;
    const bool in = u >= 0 && u < s.max_u;
    const int u0 = in ? static_cast<int>(u) : 0;
    const float fx = u - static_cast<float>(u0);
    const float value = source[u0] + fx * (source[u0 + 1] - source[u0]);
    const float d = std::abs(ref[x] - value);
    out[x] += in && d < s.implausible ? std::min(d, s.truncation) : s.invalid;
  }
}

void portableBlend(const float* top, const float* bottom, float fy, int begin, int n, float* out) {
  for (int u = begin; u < n; ++u) out[u] = top[u] + fy * (bottom[u] - top[u]);
}

#ifdef VALERANT_SWEEP_AVX2
__attribute__((target("avx2"))) void avx2Blend(const float* top, const float* bottom, float fy, int n, float* out) {
  const __m256 f = _mm256_set1_ps(fy);
  int u = 0;
  for (; u + 8 <= n; u += 8) {
    const __m256 a = _mm256_loadu_ps(top + u);
    _mm256_storeu_ps(out + u, _mm256_add_ps(a, _mm256_mul_ps(f, _mm256_sub_ps(_mm256_loadu_ps(bottom + u), a))));
  }
  portableBlend(top, bottom, fy, u, n, out);
}

// portableDifferences, 8 pixels a step. _mm256_min_ps(a, b) is a < b ? a : b, and the
// masks follow the scalar comparisons (ordered, false on NaN).
__attribute__((target("avx2"))) void avx2Differences(const float* ref, const float* source, int n,
                                                      const RowSampling& s, float* out) {
  const __m256 scale = _mm256_set1_ps(s.scale), shift = _mm256_set1_ps(s.shift), zero = _mm256_setzero_ps();
  const __m256 max_u = _mm256_set1_ps(s.max_u), truncation = _mm256_set1_ps(s.truncation);
  const __m256 implausible = _mm256_set1_ps(s.implausible), invalid = _mm256_set1_ps(s.invalid);
  const __m256 magnitude = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
  const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  int x = 0;
  for (; x + 8 <= n; x += 8) {
    const __m256 xf = _mm256_cvtepi32_ps(_mm256_add_epi32(_mm256_set1_epi32(x), lanes));
    const __m256 u = _mm256_add_ps(_mm256_mul_ps(scale, xf), shift);
    const __m256 in = _mm256_and_ps(_mm256_cmp_ps(u, zero, _CMP_GE_OQ), _mm256_cmp_ps(u, max_u, _CMP_LT_OQ));
    const __m256i u0 = _mm256_and_si256(_mm256_cvttps_epi32(u), _mm256_castps_si256(in));
    const __m256 fx = _mm256_sub_ps(u, _mm256_cvtepi32_ps(u0));
    const __m256 a = _mm256_i32gather_ps(source, u0, 4);
    const __m256 b = _mm256_i32gather_ps(source + 1, u0, 4);
    const __m256 value = _mm256_add_ps(a, _mm256_mul_ps(fx, _mm256_sub_ps(b, a)));
    const __m256 d = _mm256_and_ps(_mm256_sub_ps(_mm256_loadu_ps(ref + x), value), magnitude);
    const __m256 scored = _mm256_and_ps(in, _mm256_cmp_ps(d, implausible, _CMP_LT_OQ));
    const __m256 add = _mm256_blendv_ps(invalid, _mm256_min_ps(d, truncation), scored);
    _mm256_storeu_ps(out + x, _mm256_add_ps(_mm256_loadu_ps(out + x), add));
  }
  portableDifferences(ref, source, x, n, s, out);
}
#endif

}  // namespace

SweepIsa fastestSweepIsa() {
#ifdef VALERANT_SWEEP_AVX2
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2 ? SweepIsa::kAvx2 : SweepIsa::kPortable;
#else
  return SweepIsa::kPortable;
#endif
}

std::vector<SweepIsa> sweepIsasHere() {
  std::vector<SweepIsa> out = {SweepIsa::kPortable};
  if (fastestSweepIsa() != SweepIsa::kPortable) out.push_back(fastestSweepIsa());
  return out;
}

void blendRows(const float* top, const float* bottom, float fy, int n, float* out, SweepIsa isa) {
#ifdef VALERANT_SWEEP_AVX2
  if (isa == SweepIsa::kAvx2) return avx2Blend(top, bottom, fy, n, out);
#endif
  (void)isa;
  portableBlend(top, bottom, fy, 0, n, out);
}

void addTruncatedDifferences(const float* ref, const float* source, int n, const RowSampling& sampling, float* out,
                             SweepIsa isa) {
#ifdef VALERANT_SWEEP_AVX2
  if (isa == SweepIsa::kAvx2) return avx2Differences(ref, source, n, sampling, out);
#endif
  (void)isa;
  portableDifferences(ref, source, 0, n, sampling, out);
}

CostCurveTracker::CostCurveTracker(size_t pixels, SweepIsa isa)
    : isa_(isa), c1_(pixels, kInf), left_(pixels, kInf), right_(pixels, kInf), before_(pixels, kInf),
      after_(pixels, kInf), lag_min_(pixels, kInf), prev1_(pixels, kInf), prev2_(pixels, kInf), prev3_(pixels, kInf),
      best_(pixels, 0) {}

void CostCurveTracker::add(int plane, const float* cost, float invalid) {
#ifdef VALERANT_SWEEP_AVX2
  if (isa_ == SweepIsa::kAvx2) return addAvx2(plane, cost, invalid);
#endif
  addPortable(plane, cost, invalid, 0);
}

void CostCurveTracker::addPortable(int plane, const float* cost, float invalid, size_t begin) {
  for (size_t p = begin; p < c1_.size(); ++p) {
    const float c = cost[p] < invalid ? cost[p] : kInf;
    const float lag = std::min(lag_min_[p], prev3_[p]);  // min of planes 0 .. plane-3
    const bool better = c < c1_[p];
    const int best = best_[p];
    const float after = plane == best + 1 ? c : after_[p];
    const float right = plane > best + 2 ? std::min(right_[p], c) : right_[p];
    left_[p] = better ? lag : left_[p];
    before_[p] = better ? prev1_[p] : before_[p];
    after_[p] = better ? kInf : after;
    right_[p] = better ? kInf : right;
    c1_[p] = better ? c : c1_[p];
    best_[p] = better ? plane : best;
    lag_min_[p] = lag;
    prev3_[p] = prev2_[p], prev2_[p] = prev1_[p], prev1_[p] = c;
  }
}

#ifdef VALERANT_SWEEP_AVX2
// addPortable, 8 pixels a step (std::min(a, b) is b < a ? b : a, so _mm256_min_ps(b, a)).
__attribute__((target("avx2"))) void CostCurveTracker::addAvx2(int plane, const float* cost, float invalid) {
  const __m256 inf = _mm256_set1_ps(kInf), limit = _mm256_set1_ps(invalid);
  const __m256i planes = _mm256_set1_epi32(plane), one = _mm256_set1_epi32(1), two = _mm256_set1_epi32(2);
  const size_t n = c1_.size();
  size_t p = 0;
  for (; p + 8 <= n; p += 8) {
    const __m256 raw = _mm256_loadu_ps(cost + p);
    const __m256 c = _mm256_blendv_ps(inf, raw, _mm256_cmp_ps(raw, limit, _CMP_LT_OQ));
    const __m256 prev1 = _mm256_loadu_ps(&prev1_[p]), prev2 = _mm256_loadu_ps(&prev2_[p]);
    const __m256 lag = _mm256_min_ps(_mm256_loadu_ps(&prev3_[p]), _mm256_loadu_ps(&lag_min_[p]));
    const __m256 c1 = _mm256_loadu_ps(&c1_[p]);
    const __m256 better = _mm256_cmp_ps(c, c1, _CMP_LT_OQ);
    const __m256i best = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(&best_[p]));
    const __m256 next = _mm256_castsi256_ps(_mm256_cmpeq_epi32(planes, _mm256_add_epi32(best, one)));
    const __m256 beyond = _mm256_castsi256_ps(_mm256_cmpgt_epi32(planes, _mm256_add_epi32(best, two)));
    const __m256 after = _mm256_blendv_ps(_mm256_loadu_ps(&after_[p]), c, next);
    const __m256 right_was = _mm256_loadu_ps(&right_[p]);
    const __m256 right = _mm256_blendv_ps(right_was, _mm256_min_ps(c, right_was), beyond);
    _mm256_storeu_ps(&left_[p], _mm256_blendv_ps(_mm256_loadu_ps(&left_[p]), lag, better));
    _mm256_storeu_ps(&before_[p], _mm256_blendv_ps(_mm256_loadu_ps(&before_[p]), prev1, better));
    _mm256_storeu_ps(&after_[p], _mm256_blendv_ps(after, inf, better));
    _mm256_storeu_ps(&right_[p], _mm256_blendv_ps(right, inf, better));
    _mm256_storeu_ps(&c1_[p], _mm256_blendv_ps(c1, c, better));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(&best_[p]),
                        _mm256_blendv_epi8(best, planes, _mm256_castps_si256(better)));
    _mm256_storeu_ps(&lag_min_[p], lag);
    _mm256_storeu_ps(&prev3_[p], prev2);
    _mm256_storeu_ps(&prev2_[p], prev1);
    _mm256_storeu_ps(&prev1_[p], c);
  }
  addPortable(plane, cost, invalid, p);
}
#else
void CostCurveTracker::addAvx2(int plane, const float* cost, float invalid) { addPortable(plane, cost, invalid, 0); }
#endif

}  // namespace valerant::visual
