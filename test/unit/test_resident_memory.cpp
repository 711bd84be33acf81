// Resident memory read from a /proc/<pid>/status text.
#include <gtest/gtest.h>

#include "valerant/common/resident_memory.h"

using namespace valerant;

TEST(ResidentMemory, ParsesVmRssAndVmHwmInKilobytes) {
  const std::string status =
      "Name:\tvalerant_explore\nVmPeak:\t 9000000 kB\nVmHWM:\t  2048 kB\nVmRSS:\t    1000 kB\nThreads:\t5\n";
  const ResidentMemory m = parseResidentMemory(status);
  EXPECT_EQ(m.current_bytes, 1000u * 1024);  // 1 024 000
  EXPECT_EQ(m.peak_bytes, 2048u * 1024);     // 2 MiB
  EXPECT_EQ(parseResidentMemory("Name:\tx\n").current_bytes, 0u);
  EXPECT_EQ(parseResidentMemory("VmRSS: lots\n").current_bytes, 0u);
}

TEST(ResidentMemory, ThisProcessHoldsSomeMemory) {
  const ResidentMemory m = residentMemory();
  EXPECT_GT(m.current_bytes, 0u);
  EXPECT_GE(m.peak_bytes, m.current_bytes);
}
