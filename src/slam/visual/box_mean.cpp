#include "valerant/slam/visual/box_mean.h"

#include <opencv2/imgproc.hpp>

#include "valerant/common/error.h"

#if defined(__x86_64__)
#include <immintrin.h>
#define VALERANT_BOX_AVX2 1
#endif

namespace valerant::visual {
namespace {

// Window sums of one padded row (n outputs; `padded` holds n + window - 1 values).
void portableRowSums(const float* padded, int n, int window, int begin, double* out) {
  for (int x = begin; x < n; ++x) {
    double s = static_cast<double>(padded[x]) + static_cast<double>(padded[x + 1]) + static_cast<double>(padded[x + 2]);
    if (window == 5) s = s + static_cast<double>(padded[x + 3]) + static_cast<double>(padded[x + 4]);
    out[x] = s;
  }
}

// One output row of the running column sum.
void portableColumn(double* sum, const double* plus, const double* minus, double scale, int begin, int n, float* out) {
  for (int x = begin; x < n; ++x) {
    const double s = sum[x] + plus[x];
    out[x] = static_cast<float>(s * scale);
    sum[x] = s - minus[x];
  }
}

#ifdef VALERANT_BOX_AVX2
__attribute__((target("avx2"))) void avx2RowSums(const float* padded, int n, int window, double* out) {
  int x = 0;
  for (; x + 4 <= n; x += 4) {
    __m256d s = _mm256_add_pd(_mm256_cvtps_pd(_mm_loadu_ps(padded + x)), _mm256_cvtps_pd(_mm_loadu_ps(padded + x + 1)));
    s = _mm256_add_pd(s, _mm256_cvtps_pd(_mm_loadu_ps(padded + x + 2)));
    if (window == 5) {
      s = _mm256_add_pd(s, _mm256_cvtps_pd(_mm_loadu_ps(padded + x + 3)));
      s = _mm256_add_pd(s, _mm256_cvtps_pd(_mm_loadu_ps(padded + x + 4)));
    }
    _mm256_storeu_pd(out + x, s);
  }
  portableRowSums(padded, n, window, x, out);
}

__attribute__((target("avx2"))) void avx2Column(double* sum, const double* plus, const double* minus, double scale,
                                                 int n, float* out) {
  const __m256d k = _mm256_set1_pd(scale);
  int x = 0;
  for (; x + 4 <= n; x += 4) {
    const __m256d s = _mm256_add_pd(_mm256_loadu_pd(sum + x), _mm256_loadu_pd(plus + x));
    _mm_storeu_ps(out + x, _mm256_cvtpd_ps(_mm256_mul_pd(s, k)));
    _mm256_storeu_pd(sum + x, _mm256_sub_pd(s, _mm256_loadu_pd(minus + x)));
  }
  portableColumn(sum, plus, minus, scale, x, n, out);
}
#endif

}  // namespace

BoxMean::BoxMean(int window, SweepIsa isa) : window_(window), isa_(isa) {
  if (window < 1 || window % 2 == 0) throw InputError("box mean", "the window must be odd and positive");
}

void BoxMean::apply(const cv::Mat& src, cv::Mat& dst) {
  if (src.type() != CV_32FC1 || !src.isContinuous()) throw InputError("box mean", "needs one continuous float channel");
  if (window_ != 3 && window_ != 5) {
    cv::boxFilter(src, dst, CV_32F, cv::Size(window_, window_), cv::Point(-1, -1), true, cv::BORDER_REPLICATE);
    return;
  }
  const int w = src.cols, h = src.rows, half = window_ / 2;
  dst.create(src.size(), CV_32F);
  padded_.resize(static_cast<size_t>(w + 2 * half));
  rows_.resize(static_cast<size_t>(w) * h);
  [[maybe_unused]] const bool avx2 = isa_ == SweepIsa::kAvx2;
  for (int y = 0; y < h; ++y) {
    const float* row = src.ptr<float>(y);
    std::copy(row, row + w, padded_.begin() + half);
    std::fill(padded_.begin(), padded_.begin() + half, row[0]);
    std::fill(padded_.end() - half, padded_.end(), row[w - 1]);
    double* out = rows_.data() + static_cast<size_t>(y) * w;
#ifdef VALERANT_BOX_AVX2
    if (avx2) {
      avx2RowSums(padded_.data(), w, window_, out);
      continue;
    }
#endif
    portableRowSums(padded_.data(), w, window_, 0, out);
  }
  auto rowSums = [&](int y) { return rows_.data() + static_cast<size_t>(std::clamp(y, 0, h - 1)) * w; };
  column_.assign(static_cast<size_t>(w), 0.0);
  for (int y = -half; y < half; ++y) {
    const double* r = rowSums(y);
    for (int x = 0; x < w; ++x) column_[x] += r[x];
  }
  const double scale = 1.0 / (window_ * window_);
  for (int y = 0; y < h; ++y) {
    float* out = dst.ptr<float>(y);
#ifdef VALERANT_BOX_AVX2
    if (avx2) {
      avx2Column(column_.data(), rowSums(y + half), rowSums(y - half), scale, w, out);
      continue;
    }
#endif
    portableColumn(column_.data(), rowSums(y + half), rowSums(y - half), scale, 0, w, out);
  }
}

}  // namespace valerant::visual
