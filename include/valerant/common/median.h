#pragma once
// Order statistics of a sample, found by a partial sort of the copy. The median of a
// non-empty sample is its upper middle element (index size / 2 of the sorted values).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace valerant {

inline double median(std::vector<double> values) {
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

// The element at index floor(q size) of the sorted values (the last for q = 1); NaN for an
// empty sample. quantile(v, 0.5) is median(v).
inline double quantile(std::vector<double> values, double q) {
  if (values.empty()) return std::nan("");
  const size_t i = std::min(values.size() - 1, static_cast<size_t>(q * static_cast<double>(values.size())));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(i), values.end());
  return values[i];
}

}  // namespace valerant
