#pragma once
// Minimal "--key value" / "--flag" parser shared by the command-line tools. Unknown
// options are errors, so a typo never silently runs with defaults.
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "valerant/common/error.h"
#include "valerant/common/whole_integer.h"

namespace valerant::tools {

class CliArgs {
 public:
  // `options` take a value, `flags` do not. A tool that lists "--set" among its options
  // takes it any number of times (configuration overrides, tool_config.h).
  CliArgs(int argc, char** argv, const std::set<std::string>& options,
          const std::set<std::string>& flags = {}) {
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      if (flags.count(arg)) {
        values_[arg] = "1";
      } else if (options.count(arg)) {
        if (i + 1 >= argc) throw InputError(arg, "needs a value");
        if (arg == kSet) {
          sets_.push_back(argv[++i]);
        } else {
          values_[arg] = argv[++i];
        }
      } else {
        throw InputError(arg, "unknown option");
      }
    }
  }
  static constexpr const char* kSet = "--set";
  // Every `--set` value, in command-line order.
  const std::vector<std::string>& sets() const { return sets_; }
  bool has(const std::string& key) const { return values_.count(key) > 0; }
  std::string get(const std::string& key, const std::string& fallback = "") const {
    auto it = values_.find(key);
    return it == values_.end() ? fallback : it->second;
  }
  std::string required(const std::string& key) const {
    if (!has(key)) throw InputError(key, "is required");
    return get(key);
  }
  // A whole number that fits the fallback's type: "--spawn 99999999999" is an error
  // naming that value, never a spawn narrowed to some other number.
  template <class Integer>
  Integer integer(const std::string& key, Integer fallback) const {
    if (!has(key)) return fallback;
    if (const std::optional<Integer> v = wholeInteger<Integer>(get(key))) return *v;
    throw InputError(key + " " + get(key), "is not an integer from " +
                                               std::to_string(std::numeric_limits<Integer>::min()) + " to " +
                                               std::to_string(std::numeric_limits<Integer>::max()));
  }

  // A comma-separated value ("uw,jw,lw"); empty items are dropped and an option that
  // names nothing is an error.
  std::vector<std::string> list(const std::string& key, const std::string& fallback) const {
    const std::string text = get(key, fallback);
    std::vector<std::string> out;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');)
      if (!item.empty()) out.push_back(item);
    if (out.empty()) throw InputError(key + " '" + text + "'", "names nothing");
    return out;
  }

 private:
  std::map<std::string, std::string> values_;
  std::vector<std::string> sets_;
};

}  // namespace valerant::tools
