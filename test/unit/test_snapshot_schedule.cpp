// When a run writes its snapshot: at most a tenth of its time.
#include <gtest/gtest.h>

#include "valerant/eval/snapshot_schedule.h"

using namespace valerant;

TEST(SnapshotSchedule, WaitsNineTimesTheLastWriteSoWritingTakesATenth) {
  SnapshotSchedule schedule;  // max_share 0.1: wait 1 / 0.1 - 1 = 9 write durations
  EXPECT_TRUE(schedule.due(5));  // the first is always due
  schedule.written(10, 12);      // 2 s: due again 18 s after it ended
  EXPECT_FALSE(schedule.due(29.9));
  EXPECT_TRUE(schedule.due(30));
  schedule.written(30, 30.01);   // a small map: due again 0.09 s later, before the next step
  EXPECT_FALSE(schedule.due(30.05));
  EXPECT_TRUE(schedule.due(30.2));
  SnapshotSchedule half(0.5);    // wait one write duration
  half.written(0, 4);
  EXPECT_FALSE(half.due(7.9));
  EXPECT_TRUE(half.due(8));
}
