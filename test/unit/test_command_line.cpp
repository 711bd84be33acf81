// The tools' command lines (src/tools/command_line.h, tool_config.h,
// package_file_flag.h): --help exits 0 and lists every flag, also where the package
// folder is unknown; a bad command line is an error naming the flag and its value, exit
// status 2; integers are read whole and must fit their range; configuration overrides go
// through the strict loader, in command-line order.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "command_line.h"
#include "package_file_flag.h"
#include "tool_config.h"
#include "valerant/config/package_dir.h"

using valerant::InputError;
using valerant::tools::UsageError;

namespace {

// A test tool: --spawn INT (default 0), --seed UINT32, --maps LIST, --no-dp, --out (required).
struct TestTool {
  CLI::App app{"a test tool", "valerant_test_tool"};
  int spawn = 0;
  uint32_t seed = 0;
  std::string maps, out;
  TestTool() {
    valerant::tools::useToolConventions(app);
    valerant::tools::addInteger(app, "--spawn", spawn, "spawn point index", 0);
    valerant::tools::addInteger(app, "--seed", seed, "random seed");
    app.add_option("--maps", maps, "maps, comma-separated");
    app.add_flag("--no-dp", "no dead-pocket rewind");
    app.add_option("--out", out, "output folder")->required();
  }
};

struct Outcome {
  int status = -1;
  std::string out, err;
};

// Runs `app` on `words` through runTool with `work`; what it printed and its status.
Outcome runOn(
    CLI::App& app, std::vector<std::string> words, const std::function<int()>& work = [] { return 0; }) {
  std::vector<char*> argv;
  std::string name = app.get_name();
  argv.push_back(name.data());
  for (auto& w : words) argv.push_back(w.data());
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  Outcome o;
  o.status = valerant::tools::runTool(app, static_cast<int>(argv.size()), argv.data(), work);
  o.out = testing::internal::GetCapturedStdout();
  o.err = testing::internal::GetCapturedStderr();
  return o;
}

// Environment variables set or unset for one test, restored when it ends.
class ScopedEnvironment {
 public:
  ScopedEnvironment(std::initializer_list<std::pair<const char*, std::optional<std::string>>> values) {
    for (const auto& [name, value] : values) {
      const char* before = std::getenv(name);
      saved_[name] = before ? std::optional<std::string>(before) : std::nullopt;
      if (value)
        ::setenv(name, value->c_str(), 1);
      else
        ::unsetenv(name);
    }
  }
  ScopedEnvironment(const ScopedEnvironment&) = delete;
  ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;
  ~ScopedEnvironment() {
    for (const auto& [name, value] : saved_)
      if (value)
        ::setenv(name.c_str(), value->c_str(), 1);
      else
        ::unsetenv(name.c_str());
  }

 private:
  std::map<std::string, std::optional<std::string>> saved_;
};

// A shell without the workspace sourced: nothing says where the package is.
ScopedEnvironment withoutThePackage() {
  return {{"ROS_PACKAGE_PATH", std::nullopt},
          {"VALERANT_SHARE_DIR", std::nullopt},
          {"VALERANT_CONFIG", std::nullopt}};
}

const std::string kShipped = std::string(VALERANT_SOURCE_DIR) + "/config/valerant.yaml";

}  // namespace

TEST(CommandLine, HelpListsEveryFlagWithItsDefaultAndExitsZero) {
  for (const char* help : {"--help", "-h"}) {
    TestTool tool;
    bool worked = false;
    const Outcome o = runOn(tool.app, {help}, [&] { return worked = true, 0; });
    EXPECT_EQ(o.status, 0);
    EXPECT_FALSE(worked) << "help does no work";
    for (const char* flag : {"--spawn", "--seed", "--maps", "--no-dp", "--out", "--help"})
      EXPECT_NE(o.out.find(flag), std::string::npos) << flag;
    EXPECT_NE(o.out.find("spawn point index"), std::string::npos);
    EXPECT_NE(o.out.find("--spawn INT=0"), std::string::npos) << o.out;  // the default
    EXPECT_NE(o.out.find("REQUIRED"), std::string::npos);
  }
}

TEST(CommandLine, IntegersFitTheirRange) {
  TestTool tool;
  EXPECT_EQ(runOn(tool.app, {"--spawn", "3", "--out", "x"}).status, 0);
  EXPECT_EQ(tool.spawn, 3);
  // 99999999999 is a long but not an int (at most 2147483647): an error with the value,
  // where a narrowing cast once reported spawn 1215752191.
  for (const char* bad : {"99999999999", "2x", "-1"}) {
    TestTool again;
    const Outcome o = runOn(again.app, {"--spawn", bad, "--out", "x"});
    EXPECT_EQ(o.status, 2) << bad;
    EXPECT_NE(o.err.find(std::string("valerant_test_tool: error: --spawn: ") + bad +
                         " is not an integer from 0 to 2147483647"),
              std::string::npos)
        << o.err;
    EXPECT_NE(o.err.find("Run 'valerant_test_tool --help'"), std::string::npos) << o.err;
  }
  // A seed is unsigned 32-bit: -1 does not wrap to 4294967295.
  TestTool negative_seed;
  const Outcome o = runOn(negative_seed.app, {"--seed", "-1", "--out", "x"});
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("--seed: -1 is not an integer from 0 to 4294967295"), std::string::npos) << o.err;
  TestTool largest_seed;
  EXPECT_EQ(runOn(largest_seed.app, {"--seed", "4294967295", "--out", "x"}).status, 0);
  EXPECT_EQ(largest_seed.seed, 4294967295u);
}

TEST(CommandLine, UnknownFlagsStrayWordsAndMissingValuesAreErrorsNamingThem) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--spwan", "3", "--out", "x"}, "valerant_test_tool: error: --spwan: unknown flag"},
      {{"--out", "x", "3"}, "valerant_test_tool: error: '3': unexpected argument"},
      {{"--out", "x", "--spawn"}, "--spawn"},
      {{"--spawn", "1"}, "--out is required"}};
  for (const auto& [words, message] : cases) {
    TestTool tool;
    const Outcome o = runOn(tool.app, words);
    EXPECT_EQ(o.status, 2) << message;
    EXPECT_NE(o.err.find(message), std::string::npos) << o.err;
  }
}

TEST(CommandLine, AFlagGivenTwiceTakesItsLastValue) {
  TestTool tool;
  EXPECT_EQ(runOn(tool.app, {"--out", "x", "--spawn", "1", "--spawn", "2"}).status, 0);
  EXPECT_EQ(tool.spawn, 2);
}

TEST(CommandLine, WorkErrorsExitOneAndUsageErrorsTwo) {
  TestTool tool;
  Outcome o = runOn(tool.app, {"--out", "x"}, []() -> int { throw InputError("map.bsp", "cannot read"); });
  EXPECT_EQ(o.status, 1);
  EXPECT_EQ(o.err, "valerant_test_tool: error: map.bsp: cannot read\n");
  TestTool again;
  o = runOn(again.app, {"--out", "x"}, []() -> int { throw UsageError("--maps ','", "names nothing"); });
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("--maps ',': names nothing"), std::string::npos);
}

TEST(CommandLine, CommaListsDropEmptyItemsAndMustNameSomething) {
  EXPECT_EQ(valerant::tools::commaList("--maps", "oa_dm1,,oa_dm5"), (std::vector<std::string>{"oa_dm1", "oa_dm5"}));
  EXPECT_THROW(valerant::tools::commaList("--maps", ","), UsageError);
  EXPECT_THROW(valerant::tools::commaList("--maps", ""), UsageError);
}

TEST(CommandLine, CheckedFlagValuesAreTheCommandLinesFault) {
  EXPECT_THROW(valerant::tools::checkFlagValues([]() -> int { throw InputError("action string 'x'", "bad"); }),
               UsageError);
  EXPECT_EQ(valerant::tools::checkFlagValues([] { return 4; }), 4);
}

TEST(CommandLine, SubcommandsHaveTheirOwnHelpAndErrors) {
  CLI::App app{"benchmarks", "valerant_test_bench"};
  valerant::tools::useToolConventions(app);
  app.require_subcommand(1);
  CLI::App* render = app.add_subcommand("render", "renders");
  long frames = 1000;
  valerant::tools::addInteger(*render, "--frames", frames, "frames to render", 1L);
  Outcome o = runOn(app, {"render", "--help"});
  EXPECT_EQ(o.status, 0);
  EXPECT_NE(o.out.find("--frames INT=1000"), std::string::npos) << o.out;
  o = runOn(app, {"render", "--frames", "0"});
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("--frames: 0 is not an integer from 1 to 9223372036854775807"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("Run 'valerant_test_bench render --help'"), std::string::npos) << o.err;
  o = runOn(app, {"render", "--franes", "3"});
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("--franes: unknown flag"), std::string::npos) << o.err;
  o = runOn(app, {});
  EXPECT_EQ(o.status, 2);
  o = runOn(app, {"rendre"});
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("'rendre': unknown subcommand (one of: render)"), std::string::npos) << o.err;
}

TEST(ToolConfig, OverridesGoThroughTheLoaderInCommandLineOrder) {
  CLI::App app{"a test tool", "valerant_test_tool"};
  valerant::tools::useToolConventions(app);
  valerant::tools::ToolConfig config(app);
  config.keyFlag("--budget", "policy.budget_steps", "INT", "steps to commit");
  config.keyFlag("--width", "world.width", "INT", "frame width", "128");
  config.switchFlag("--no-dp", "dead_pocket.enabled=false", "no dead-pocket rewind");
  Outcome o = runOn(app, {"--budget", "7", "--no-dp", "--set", "policy.budget_steps=9", "--set", "world.spawn=2"}, [&] {
    const valerant::Config c = config.document().parse();
    EXPECT_EQ(c.policy.budget_steps, 9);  // --set comes after the flags
    EXPECT_EQ(c.world.spawn, 2);
    EXPECT_EQ(c.world.width, 128);  // a tool default sets its key unasked
    EXPECT_FALSE(c.dead_pocket.enabled);
    EXPECT_EQ(config.sets(), (std::vector<std::string>{"policy.budget_steps=9", "world.spawn=2"}));
    EXPECT_EQ(config.givenFlags(), (std::vector<std::string>{"--budget", "--no-dp", "--set"}));
    return 0;
  });
  EXPECT_EQ(o.status, 0) << o.err;
}

TEST(ToolConfig, ABadOverrideIsAUsageErrorNamingItAndABadFileIsNot) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--budget", "0"}, "--budget 0: policy.budget_steps: value 0 outside"},
      {{"--budget", "many"}, "--budget many"},
      {{"--set", "policy.budget_step=3"}, "policy.budget_step: unknown key"},
      {{"--set", "collision.body_radius=-1"}, "collision.body_radius: value -1 outside"},
      {{"--set", "policy.budget_steps"}, "--set policy.budget_steps: expected key=value"}};
  for (const auto& [words, message] : cases) {
    CLI::App app{"a test tool", "valerant_test_tool"};
    valerant::tools::ToolConfig config(app);
    config.keyFlag("--budget", "policy.budget_steps", "INT", "steps to commit");
    const Outcome o = runOn(app, words, [&] { return config.document().parse(), 0; });
    EXPECT_EQ(o.status, 2) << message;
    EXPECT_NE(o.err.find(message), std::string::npos) << o.err;
  }
  // A file the loader refuses is the file's fault (exit 1), whatever the overrides.
  const std::string cut = testing::TempDir() + "valerant_cut_config.yaml";
  std::ofstream(cut) << "world: {}\n";
  CLI::App app{"a test tool", "valerant_test_tool"};
  valerant::tools::ToolConfig config(app);
  const Outcome o =
      runOn(app, {"--config", cut, "--set", "policy.budget_steps=0"}, [&] { return config.document().parse(), 0; });
  EXPECT_EQ(o.status, 1);
  EXPECT_NE(o.err.find(cut), std::string::npos) << o.err;
}

TEST(PackageFileFlag, WithoutThePackageHelpWorksAndARunNamesTheFlagAndTheEnvironment) {
  const ScopedEnvironment environment = withoutThePackage();
  // Making the flags once threw the package's InputError outside runTool: every tool
  // aborted (SIGABRT), --help included.
  CLI::App help_app{"a test tool", "valerant_test_tool"};
  valerant::tools::useToolConventions(help_app);
  const valerant::tools::ToolConfig help_config(help_app);
  Outcome o = runOn(help_app, {"--help"});
  EXPECT_EQ(o.status, 0);
  EXPECT_NE(o.out.find("--config FILE=the package's config/valerant.yaml (package not found)"),
            std::string::npos)
      << o.out;
  // A run that reads the default fails as the environment's fault (exit 1), not the
  // command line's, and says what to do.
  CLI::App app{"a test tool", "valerant_test_tool"};
  const valerant::tools::ToolConfig config(app);
  o = runOn(app, {}, [&] { return config.document().parse(), 0; });
  EXPECT_EQ(o.status, 1);
  EXPECT_EQ(o.err.rfind("valerant_test_tool: error: --config left out: the package's config/valerant.yaml: "
                        "ROS_PACKAGE_PATH='': no folder there holds the valerant package",
                        0),
            0u)
      << o.err;
  EXPECT_NE(o.err.find("VALERANT_SHARE_DIR"), std::string::npos) << o.err;
  // --config names the file: no package needed.
  CLI::App given_app{"a test tool", "valerant_test_tool"};
  const valerant::tools::ToolConfig given_config(given_app);
  o = runOn(given_app, {"--config", kShipped}, [&] {
    EXPECT_EQ(given_config.file(), kShipped);
    return given_config.document().parse(), 0;
  });
  EXPECT_EQ(o.status, 0) << o.err;
}

TEST(PackageFileFlag, HelpShowsTheDefaultsPathWhenThePackageIsFound) {
  const std::string share = std::filesystem::canonical(VALERANT_SOURCE_DIR).string();
  const ScopedEnvironment environment = {{"VALERANT_SHARE_DIR", share}, {"VALERANT_CONFIG", std::nullopt}};
  CLI::App app{"a test tool", "valerant_test_tool"};
  const valerant::tools::PackageFileFlag sets(
      app, "--map-sets", "the held-out map sets",
      [] { return valerant::packageFilePath("config/map_sets.yaml"); }, "config/map_sets.yaml");
  const Outcome o = runOn(app, {"--help"});
  EXPECT_EQ(o.status, 0);
  EXPECT_NE(o.out.find("--map-sets FILE=" + share + "/config/map_sets.yaml"), std::string::npos) << o.out;
  EXPECT_FALSE(sets.given());
  EXPECT_EQ(sets.path(), share + "/config/map_sets.yaml");
}

TEST(CommandLine, AnEmptyPathIsAnErrorNamingTheFlag) {
  // valerant_eval --out '' once wrote its grid into the root folder ("" + "/runs").
  for (const char* type : {"DIR", "FILE"}) {
    CLI::App app{"a test tool", "valerant_test_tool"};
    std::string out;
    valerant::tools::addPath(app, "--out", out, "output folder", type);
    bool worked = false;
    const Outcome o = runOn(app, {"--out", ""}, [&] { return worked = true, 0; });
    EXPECT_EQ(o.status, 2);
    EXPECT_FALSE(worked);
    EXPECT_NE(o.err.find(std::string("valerant_test_tool: error: --out: an empty value names no ") +
                         (type == std::string("DIR") ? "folder" : "file")),
              std::string::npos)
        << o.err;
    EXPECT_EQ(runOn(app, {"--out", "x"}).status, 0);
    EXPECT_EQ(out, "x");
  }
  CLI::App app{"a test tool", "valerant_test_tool"};
  const valerant::tools::ToolConfig config(app);  // --config is such a flag too
  const Outcome o = runOn(app, {"--config", ""});
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("--config: an empty value names no file"), std::string::npos) << o.err;
}
