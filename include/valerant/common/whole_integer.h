#pragma once
// The integer that `text` is in full ("31"; not "31x", "" or out of Integer's range),
// read as std::stol reads it. Shared by action strings and command-line options.
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

namespace valerant {

template <class Integer = long>
std::optional<Integer> wholeInteger(const std::string& text) {
  try {
    size_t used = 0;
    const long value = std::stol(text, &used);
    if (used == text.size() && value >= std::numeric_limits<Integer>::min() &&
        value <= std::numeric_limits<Integer>::max())
      return static_cast<Integer>(value);
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

}  // namespace valerant
