#pragma once
// The median of a non-empty sample: its upper middle element (index size / 2 of the
// sorted values), found by a partial sort of the copy.
#include <algorithm>
#include <cstddef>
#include <vector>

namespace valerant {

inline double median(std::vector<double> values) {
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

}  // namespace valerant
