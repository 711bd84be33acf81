#pragma once
// Names in one string, e.g. for "unknown (known: a, b, c)" errors.
#include <string>

namespace valerant {

template <class Names>
std::string joined(const Names& names, const std::string& separator = ", ") {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : separator) + n;
  return out;
}

}  // namespace valerant
