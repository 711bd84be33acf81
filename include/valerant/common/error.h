#pragma once
// One error type for bad input: the message always names the offending input
// (file, map, key, action string) so a user can fix it without a debugger.
#include <stdexcept>
#include <string>

namespace valerant {

class InputError : public std::runtime_error {
 public:
  InputError(const std::string& input, const std::string& problem)
      : std::runtime_error(input + ": " + problem), input_(input) {}
  const std::string& input() const { return input_; }

 private:
  std::string input_;
};

}  // namespace valerant
