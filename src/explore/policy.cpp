#include "valerant/explore/policy.h"

#include <random>
#include <utility>

namespace valerant {

namespace {

// First admissible candidate with the largest key (earlier candidates win ties).
template <typename Key>
int argmaxBy(const std::vector<BranchVerdict>& verdicts, Key key) {
  int best = -1;
  for (size_t i = 0; i < verdicts.size(); ++i)
    if (verdicts[i].admissible && (best < 0 || key(verdicts[i]) > key(verdicts[best]))) best = static_cast<int>(i);
  return best;
}

}  // namespace

int selectBranch(std::vector<BranchVerdict>& verdicts, const PolicyConfig& config, uint64_t step_seed) {
  for (size_t i = 0; i < verdicts.size(); ++i) {
    BranchVerdict& v = verdicts[i];
    v.score = config.lambda_cov * v.coverage + config.lambda_prog * v.progress + config.goal_weight * v.goal +
              config.opening_weight * v.opening;
    std::string reason;
    if (v.slam_lost) reason += "slam lost;";
    if (v.floor_unknown) reason += "floor unknown;";
    if (v.collision_pc) reason += "point-cloud collision;";
    if (v.collision_depth) reason += "depth collision;";
    if (v.turn_in_contact) reason += "turn in place while in contact;";
    if (v.ends_in_contact) reason += "ends in contact;";
    if (v.enters_failed) reason += "enters failed region;";
    if (v.rewound_before) reason += "heads into a pocket rewound from here;";
    if (v.short_unclear) reason += "short action not clear to its end;";
    if (config.max_progress > 0 && !(v.progress <= config.max_progress)) reason += "implausible motion;";
    if (!reason.empty()) reason.pop_back();
    v.reason = reason;
    v.admissible = reason.empty();
  }
  if (config.kind == "random") {
    std::vector<int> admissible;
    for (size_t i = 0; i < verdicts.size(); ++i)
      if (verdicts[i].admissible) admissible.push_back(static_cast<int>(i));
    if (admissible.empty()) return -1;
    std::mt19937_64 rng(step_seed);
    return admissible[std::uniform_int_distribution<size_t>(0, admissible.size() - 1)(rng)];
  }
  if (config.kind == "forward") {
    for (const BranchVerdict& v : verdicts)
      if (v.admissible && !v.rotation_only && v.candidate == "uw") return static_cast<int>(&v - verdicts.data());
    for (const BranchVerdict& v : verdicts)
      if (v.admissible && v.rotation_only) return static_cast<int>(&v - verdicts.data());
    return argmaxBy(verdicts, [](const BranchVerdict& v) { return v.score; });
  }
  if (config.kind == "frontier")
    return argmaxBy(verdicts, [](const BranchVerdict& v) { return std::make_pair(v.c_front, v.coverage); });
  // [ours] A turn back (policy.no_turn_back) only where nothing else is admissible.
  return argmaxBy(verdicts, [](const BranchVerdict& v) { return std::make_pair(!v.turns_back, v.score); });
}

}  // namespace valerant
