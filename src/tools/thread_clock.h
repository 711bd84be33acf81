#pragma once
// Wall and CPU time of the calling thread, for the tools that report frames per second:
// on a shared or virtual machine the CPU time is the cost of the algorithm, the wall
// time what a user waits.
#include <chrono>
#include <ctime>

namespace valerant::tools {

struct ThreadClock {
  double wall = 0, cpu = 0;
  static ThreadClock now() {
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return {std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(),
            static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec)};
  }
  ThreadClock operator-(const ThreadClock& o) const { return {wall - o.wall, cpu - o.cpu}; }
  ThreadClock& operator+=(const ThreadClock& o) {
    wall += o.wall, cpu += o.cpu;
    return *this;
  }
};

}  // namespace valerant::tools
