#pragma once
// Wall time spent per stage of an exploration step (reports and the overhead figures).
#include <chrono>

namespace valerant {

// Seconds since `t` on the steady clock: what each stage adds to its StageSeconds.
inline double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

struct StageSeconds {
  double render = 0, slam = 0, floor = 0, collision = 0, policy = 0, fusion = 0;
  StageSeconds& operator+=(const StageSeconds& o) {
    render += o.render, slam += o.slam, floor += o.floor;
    collision += o.collision, policy += o.policy, fusion += o.fusion;
    return *this;
  }
};

}  // namespace valerant
