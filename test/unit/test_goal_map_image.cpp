// The goal map (goal_map_image.h) of the hand-built walled room (walled_room_grid.h), one
// pixel a cell: the start heading (+x) points up, +y left, cropped to the known cells
// (x -1..5, y -2..2) with a margin of two cells, so cell (x, y) is at row 7 - x, column 4 - y.
#include <gtest/gtest.h>

#include "valerant/explore/goal_map_image.h"
#include "walled_room_grid.h"

using namespace valerant;
using valerant::test::roomCell;

namespace {

cv::Vec3b at(const cv::Mat& image, int x, int y) { return image.at<cv::Vec3b>(7 - x, 4 - y); }

}  // namespace

TEST(GoalMapImage, ColoursWhatTheGoalCanReach) {
  const CoverageGrid g = test::walledRoomGrid();
  FailedRegionMemory none;
  const cv::Mat open = drawGoalMap(g, FrontierDistance(g, {}), none, roomCell(3, 0), 1);
  ASSERT_EQ(open.rows, 11);
  ASSERT_EQ(open.cols, 9);
  EXPECT_EQ(at(open, 3, 0), cv::Vec3b(255, 255, 255));  // the agent
  EXPECT_EQ(at(open, 0, 0), cv::Vec3b(60, 220, 230));   // the doorway's frontier
  EXPECT_EQ(at(open, 2, 1), cv::Vec3b(70, 150, 70));    // floor the goal is reachable from
  EXPECT_EQ(at(open, 5, 0), cv::Vec3b(110, 30, 30));    // the east wall
  EXPECT_EQ(at(open, -1, 0), cv::Vec3b(24, 24, 32));    // the unknown doorway
  // F across the room at x = 1 cuts the agent's side off the frontier.
  FailedRegionMemory across;
  across.add({roomCell(1, -1), roomCell(1, 0), roomCell(1, 1)});
  const cv::Mat cut = drawGoalMap(g, FrontierDistance(g, across.cells()), across, roomCell(3, 0), 1);
  EXPECT_EQ(at(cut, 1, 0), cv::Vec3b(200, 40, 40));
  EXPECT_EQ(at(cut, 2, 1), cv::Vec3b(110, 110, 110));  // no frontier reachable from here
  EXPECT_EQ(at(cut, 0, 1), cv::Vec3b(70, 150, 70));    // the doorway's side still reaches it
  EXPECT_EQ(at(cut, 0, 0), cv::Vec3b(60, 220, 230));
  // With dead_pocket.cross_failed the goal's paths cross F: the agent's side is green again.
  const cv::Mat crossed = drawGoalMap(g, FrontierDistance(g, {}, across.cells()), across, roomCell(3, 0), 1);
  EXPECT_EQ(at(crossed, 1, 0), cv::Vec3b(200, 40, 40));
  EXPECT_EQ(at(crossed, 2, 1), cv::Vec3b(70, 150, 70));
}
