// The command-line parser of the tools (src/tools/cli_args.h): bad options are errors
// naming the option and its value, integers are read whole and must fit their type.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "cli_args.h"

using valerant::InputError;
using valerant::tools::CliArgs;

namespace {

CliArgs parse(std::vector<std::string> words) {
  std::vector<char*> argv;
  static std::string tool = "valerant_test_tool";
  argv.push_back(tool.data());
  for (auto& w : words) argv.push_back(w.data());
  return CliArgs(static_cast<int>(argv.size()), argv.data(), {"--spawn", "--seed", "--maps"}, {"--no-dp"});
}

std::string errorOf(const CliArgs& args, const std::string& key) {
  try {
    args.integer(key, int{0});
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(CliArgs, IntegersFitTheirType) {
  EXPECT_EQ(parse({"--spawn", "3"}).integer("--spawn", 0), 3);
  EXPECT_EQ(parse({}).integer("--spawn", 7), 7);  // absent: the fallback
  // 99999999999 is a long but not an int (at most 2147483647): an error with the value,
  // where a narrowing cast once reported spawn 1215752191.
  EXPECT_EQ(errorOf(parse({"--spawn", "99999999999"}), "--spawn"),
            "--spawn 99999999999: is not an integer from -2147483648 to 2147483647");
  EXPECT_EQ(errorOf(parse({"--spawn", "2x"}), "--spawn"), "--spawn 2x: is not an integer from -2147483648 to 2147483647");
  // A seed is unsigned 32-bit: -1 does not wrap to 4294967295.
  EXPECT_THROW(parse({"--seed", "-1"}).integer("--seed", uint32_t{0}), InputError);
  EXPECT_EQ(parse({"--seed", "4294967295"}).integer("--seed", uint32_t{0}), 4294967295u);
}

TEST(CliArgs, UnknownOptionsAndMissingValuesAreErrors) {
  EXPECT_THROW(parse({"--spwan", "3"}), InputError);
  EXPECT_THROW(parse({"--spawn"}), InputError);
  EXPECT_TRUE(parse({"--no-dp"}).has("--no-dp"));
  EXPECT_THROW(parse({"--maps", ","}).list("--maps", ""), InputError);
  EXPECT_EQ(parse({"--maps", "oa_dm1,,oa_dm5"}).list("--maps", ""), (std::vector<std::string>{"oa_dm1", "oa_dm5"}));
}

TEST(CliArgs, SetIsRepeatableWhereAToolTakesIt) {
  EXPECT_THROW(parse({"--set", "policy.budget_steps=3"}), InputError);  // this tool does not take --set
  std::vector<std::string> words = {"valerant_test_tool", "--set", "a.b=1", "--spawn", "2", "--set", "c.d=x"};
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  const CliArgs args(static_cast<int>(argv.size()), argv.data(), {"--spawn", "--set"});
  EXPECT_EQ(args.sets(), (std::vector<std::string>{"a.b=1", "c.d=x"}));
  EXPECT_EQ(args.integer("--spawn", 0), 2);
}
