// The graph explorer's configuration (valerant/ros/graph_config.h explorerConfig): what
// the graph cannot carry is an error naming the key, the rest parses as the file says.
// Needs no ROS master.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "valerant/common/error.h"
#include "valerant/ros/graph_config.h"

namespace valerant::bridge {
namespace {

ConfigDocument shippedWith(const std::vector<std::string>& assignments) {
  ConfigDocument document = ConfigDocument::load(std::string(VALERANT_SOURCE_DIR) + "/config/valerant.yaml");
  for (const std::string& a : assignments) document.setAssignment(a, "--set " + a);
  return document;
}

TEST(ExplorerConfig, LoopClosureRunsInTheGraphOnlyWithoutLoopCandidates) {
  EXPECT_FALSE(explorerConfig(shippedWith({})).loop_closure.enabled);
  try {
    explorerConfig(shippedWith({"loop_closure.enabled=true"}));
    ADD_FAILURE() << "loop candidates need rollout images the explorer never gets";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("loop_closure.max_candidates: 3 with loop_closure.enabled is not supported in "
                                         "the ROS graph"),
              std::string::npos)
        << e.what();
  }
  // The eye height alone reads only the keyframes' floors.
  const Config eye_height = explorerConfig(shippedWith(
      {"loop_closure.enabled=true", "loop_closure.max_candidates=0", "loop_closure.eye_height_weight=1"}));
  EXPECT_TRUE(eye_height.loop_closure.enabled);
  EXPECT_EQ(eye_height.loop_closure.eye_height_weight, 1.0);
  // A bad value is the parser's error, as for every node.
  EXPECT_THROW(explorerConfig(shippedWith({"loop_closure.max_candidates=-1"})), InputError);
}

}  // namespace
}  // namespace valerant::bridge
