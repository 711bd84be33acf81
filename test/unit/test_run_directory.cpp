// A run directory's states and how a tool may start in each (eval/run_directory.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "valerant/common/error.h"
#include "valerant/eval/run_directory.h"

using namespace valerant;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("valerant_test_run_dir_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void writeText(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

std::string errorOf(const fs::path& dir, RunStart start) {
  try {
    prepareRunDirectory(dir.string(), start);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(RunDirectory, StatesFollowTheFilesARunWrites) {
  const auto dir = scratch("states");
  EXPECT_EQ(runState((dir / "absent").string()), RunState::kNone);
  EXPECT_EQ(runState(dir.string()), RunState::kNone);
  writeText(dir / "explore.log", "valerant_eval's log of the child, not a run file\n");
  EXPECT_EQ(runState(dir.string()), RunState::kNone);
  writeText(dir / "config.yaml", "world: {}\n");
  EXPECT_EQ(runState(dir.string()), RunState::kUnfinished);
  writeText(dir / "report.json", "{\"tool\": \"valerant_ex");  // cut: still unfinished
  EXPECT_EQ(runState(dir.string()), RunState::kUnfinished);
  writeText(dir / "report.json", "[]");
  EXPECT_EQ(runState(dir.string()), RunState::kUnfinished);
  writeText(dir / "report.json", "{\"tool\": \"valerant_explore\"}");
  EXPECT_EQ(runState(dir.string()), RunState::kComplete);
}

TEST(RunDirectory, EachStartIsAllowedOnlyWhereItMakesSense) {
  const auto dir = scratch("starts");
  EXPECT_EQ(errorOf(dir, RunStart::kNew), "");
  EXPECT_NE(errorOf(dir, RunStart::kResume).find("holds no run to resume"), std::string::npos);
  writeText(dir / "config.yaml", "world: {}\n");
  writeText(dir / ".map.pcd.partial-12-0", "a temporary file a kill left");
  EXPECT_NE(errorOf(dir, RunStart::kNew).find("pass --resume to continue it or --force to replace it"),
            std::string::npos);
  EXPECT_EQ(errorOf(dir, RunStart::kResume), "");
  EXPECT_FALSE(fs::exists(dir / ".map.pcd.partial-12-0"));  // resuming clears what a kill left
  writeText(dir / "report.json", "{\"tool\": \"valerant_explore\"}");
  EXPECT_NE(errorOf(dir, RunStart::kNew).find("holds a finished run already"), std::string::npos);
  EXPECT_NE(errorOf(dir, RunStart::kResume).find("nothing to resume"), std::string::npos);
  // --force removes the run's files and nothing else.
  writeText(dir / "explore.log", "kept");
  fs::create_directories(dir / "snapshot");
  EXPECT_EQ(errorOf(dir, RunStart::kForce), "");
  EXPECT_EQ(runState(dir.string()), RunState::kNone);
  EXPECT_TRUE(fs::exists(dir / "explore.log"));
  EXPECT_FALSE(fs::exists(dir / "snapshot"));
}

TEST(RunDirectory, RecordedDecisionsDropALineCutByAKill) {
  const auto dir = scratch("decisions");
  writeText(dir / "decisions.jsonl", "{\"step\": 1, \"chosen\": \"jw\"}\n{\"step\": 2, \"chosen\": \"uw\"}\n{\"step\": 3, \"cho");
  const auto decisions = recordedDecisions(dir.string());
  ASSERT_EQ(decisions.size(), 2u);
  EXPECT_EQ(decisions[1]["chosen"], "uw");
  std::ifstream in(dir / "decisions.jsonl");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), "{\"step\": 1, \"chosen\": \"jw\"}\n{\"step\": 2, \"chosen\": \"uw\"}\n");  // cut back
  writeText(dir / "decisions.jsonl", "{\"step\": 1}\nnot json\n");
  EXPECT_THROW(recordedDecisions(dir.string()), InputError);
}

TEST(RunDirectory, AReplayMustDecideAsRecordedButMayTakeOtherTimes) {
  const nlohmann::json recorded = {{"step", 2}, {"checkpoint", 7}, {"chosen", "jw"}, {"stall", false},
                                   {"rewind", false}, {"rewind_to", 0}, {"wall_seconds", 3.5}};
  nlohmann::json replayed = recorded;
  replayed["wall_seconds"] = 9.0;
  EXPECT_NO_THROW(requireSameDecision("/run", recorded, replayed));
  replayed["chosen"] = "lq";
  try {
    requireSameDecision("/run", recorded, replayed);
    FAIL() << "a different choice was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "/run/decisions.jsonl: step 2: the resumed episode's chosen is \"lq\" where the recorded run's is \"jw\": "
              "the run cannot be continued (pass --force to replace it)");
  }
}
