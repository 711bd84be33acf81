#include "valerant/explore/policy.h"

namespace valerant {

int selectBranch(std::vector<BranchVerdict>& verdicts, const PolicyConfig& config) {
  int best = -1;
  for (size_t i = 0; i < verdicts.size(); ++i) {
    BranchVerdict& v = verdicts[i];
    v.score = config.lambda_cov * v.coverage + config.lambda_prog * v.progress;
    std::string reason;
    if (v.slam_lost) reason += "slam lost;";
    if (v.collision_pc) reason += "point-cloud collision;";
    if (v.collision_depth) reason += "depth collision;";
    if (v.enters_failed) reason += "enters failed region;";
    if (!reason.empty()) reason.pop_back();
    v.reason = reason;
    v.admissible = reason.empty();
    if (v.admissible && (best < 0 || v.score > verdicts[best].score)) best = static_cast<int>(i);
  }
  return best;
}

}  // namespace valerant
