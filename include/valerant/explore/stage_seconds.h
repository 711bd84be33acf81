#pragma once
// Wall time spent per stage of an exploration step (reports and the overhead figures).

namespace valerant {

struct StageSeconds {
  double render = 0, slam = 0, floor = 0, collision = 0, policy = 0, fusion = 0;
  StageSeconds& operator+=(const StageSeconds& o) {
    render += o.render, slam += o.slam, floor += o.floor;
    collision += o.collision, policy += o.policy, fusion += o.fusion;
    return *this;
  }
};

}  // namespace valerant
