#pragma once
// The command line of every tool, through CLI11. `--help` (`-h`) prints every flag with
// its meaning and default and exits 0. A wrong command line (an unknown flag, a missing
// or bad value, a missing required flag, flags that exclude each other) is an error
// naming the flag and its value, with a pointer to --help and exit status 2; an error of
// the work itself (a file that does not load, a failed run) exits 1.
#include <CLI/CLI.hpp>
#include <functional>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "valerant/common/error.h"
#include "valerant/common/whole_integer.h"

namespace valerant::tools {

constexpr int kUsageErrorStatus = 2;

// The command line is wrong in a way only the tool can tell (a list naming nothing, a
// configuration override the loader refuses): exit status 2, as CLI11's own errors.
class UsageError : public InputError {
 public:
  using InputError::InputError;
};

// `e` as the command line's fault, same message.
inline UsageError asUsageError(const InputError& e) {
  return UsageError(e.input(), std::string(e.what()).substr(e.input().size() + 2));
}

// The check of an integer flag: the whole text is an integer from `min` to `max`, so
// "--spawn 99999999999" is an error naming that value, never a spawn narrowed to some
// other number.
template <class Integer>
CLI::Validator integerFrom(Integer min, Integer max = std::numeric_limits<Integer>::max()) {
  return CLI::Validator(
      [min, max](std::string& text) -> std::string {
        const std::optional<Integer> value = wholeInteger<Integer>(text);
        if (value && *value >= min && *value <= max) return "";
        return text + " is not an integer from " + std::to_string(min) + " to " + std::to_string(max);
      },
      "");
}

// An integer flag bound to `value`, whose initial value is its default.
template <class Integer>
CLI::Option* addInteger(CLI::App& app, const std::string& flag, Integer& value, const std::string& meaning,
                        Integer min = std::numeric_limits<Integer>::min(),
                        Integer max = std::numeric_limits<Integer>::max()) {
  return app.add_option(flag, value, meaning)->capture_default_str()->check(integerFrom(min, max));
}

// A flag whose value is a file or a folder (`type` FILE or DIR). An empty value names
// neither: it is an error naming the flag, where "" + "/runs" once put valerant_eval's
// grid in the root folder.
template <class Value>
CLI::Option* addPath(CLI::App& app, const std::string& flag, Value& value, const std::string& meaning,
                     const std::string& type) {
  const std::string kind = type == "DIR" ? "folder" : "file";
  const CLI::Validator names_a_path(
      [kind](std::string& text) { return text.empty() ? "an empty value names no " + kind : std::string(); },
      "");
  return app.add_option(flag, value, meaning)->type_name(type)->check(names_a_path);
}

// Runs `check` of flag values (an action string, a map list): the InputError it throws
// is the command line's fault, exit status 2.
template <class Check>
auto checkFlagValues(Check&& check) -> decltype(check()) {
  try {
    return check();
  } catch (const UsageError&) {
    throw;
  } catch (const InputError& e) {
    throw asUsageError(e);
  }
}

// The items of a comma-separated value of `flag` ("uw,jw,lw"); empty items are dropped
// and a value that names nothing is an error.
inline std::vector<std::string> commaList(const std::string& flag, const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) items.push_back(item);
  if (items.empty()) throw UsageError(flag + " '" + text + "'", "names nothing");
  return items;
}

// The conventions every tool's command line shares, for the flags added after it: a
// stray word or an unknown flag is an error naming it (CLI11's own message lists such
// words backwards), a flag given twice takes its last value (so a script can append an
// override), and the help ends with the exit statuses.
inline void useToolConventions(CLI::App& app) {
  app.allow_extras();
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app.get_formatter()->column_width(34);
  app.footer("Exit status: 0 done, 1 failed, 2 bad command line.");
}

namespace detail {

// `app` and the subcommands it ran, as the user typed them ("valerant_bench slam").
inline std::string commandPath(const CLI::App& app) {
  std::string path = app.get_name();
  for (const CLI::App* sub = &app; !sub->get_subcommands().empty();) {
    sub = sub->get_subcommands().front();
    path += " " + sub->get_name();
  }
  return path;
}

// The words no flag took, named: the first is an unknown flag or a stray word.
inline void refuseExtras(const CLI::App& app) {
  for (const CLI::App* sub = &app;;) {
    const std::vector<std::string> extras = sub->remaining();
    if (!extras.empty()) {
      const std::string& word = extras.front();
      if (word.rfind("-", 0) == 0) throw UsageError(word, "unknown flag");
      if (sub->get_subcommands().empty()) {  // none given where one is wanted: a mistyped one
        const auto known = sub->get_subcommands([](const CLI::App*) { return true; });
        std::string names;
        for (const CLI::App* k : known) names += (names.empty() ? "" : ", ") + k->get_name();
        if (!known.empty()) throw UsageError("'" + word + "'", "unknown subcommand (one of: " + names + ")");
      }
      throw UsageError("'" + word + "'", "unexpected argument (every value follows its flag)");
    }
    if (sub->get_subcommands().empty()) return;
    sub = sub->get_subcommands().front();
  }
}

inline int usageError(const CLI::App& app, const std::string& message) {
  const std::string path = commandPath(app);
  std::cerr << path << ": error: " << message << "\nRun '" << path << " --help' for every flag." << std::endl;
  return kUsageErrorStatus;
}

}  // namespace detail

// Parses the command line into `app`'s bound variables, then runs `work`, which returns
// the exit status; prints help or the error as the header above says.
inline int runTool(CLI::App& app, int argc, char** argv, const std::function<int()>& work) {
  try {
    app.parse(argc, argv);
    detail::refuseExtras(app);
  } catch (const CLI::CallForHelp& help) {
    return app.exit(help);  // the help of the subcommand asked about, on stdout
  } catch (const CLI::ParseError& e) {
    // A word no flag took explains most errors ("valerant_bench rendre": not "a
    // subcommand is required"), so it is named first.
    try {
      detail::refuseExtras(app);
    } catch (const UsageError& extra) {
      return detail::usageError(app, extra.what());
    }
    return detail::usageError(app, e.what());
  } catch (const UsageError& e) {
    return detail::usageError(app, e.what());
  }
  try {
    return work();
  } catch (const UsageError& e) {
    return detail::usageError(app, e.what());
  } catch (const std::exception& e) {
    std::cerr << detail::commandPath(app) << ": error: " << e.what() << std::endl;
    return 1;
  }
}

}  // namespace valerant::tools
