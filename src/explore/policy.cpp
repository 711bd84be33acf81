#include "valerant/explore/policy.h"

#include <algorithm>
#include <random>
#include <utility>

namespace valerant {

namespace {

// One reason a candidate is inadmissible: its key (the verdict's field where it has one, as
// policy.yielding_objections names it) and the text the reason lists.
struct Objection {
  const char* key;
  const char* text;
};

std::vector<Objection> objectionsTo(const BranchVerdict& v, const PolicyConfig& config) {
  std::vector<Objection> out;
  if (v.slam_lost) out.push_back({"slam_lost", "slam lost"});
  if (v.floor_unknown) out.push_back({"floor_unknown", "floor unknown"});
  if (v.collision_pc) out.push_back({"collision_pc", "point-cloud collision"});
  if (v.collision_depth) out.push_back({"collision_depth", "depth collision"});
  if (v.turn_in_contact) out.push_back({"turn_in_contact", "turn in place while in contact"});
  if (v.ends_in_contact) out.push_back({"ends_in_contact", "ends in contact"});
  if (v.enters_failed) out.push_back({"enters_failed", "enters failed region"});
  if (v.rewound_before) out.push_back({"rewound_before", "heads into a pocket rewound from here"});
  if (v.short_unclear) out.push_back({"short_unclear", "short action not clear to its end"});
  if (config.max_progress > 0 && !(v.progress <= config.max_progress))
    out.push_back({"implausible_motion", "implausible motion"});
  return out;
}

bool allYield(const std::vector<Objection>& objections, const PolicyConfig& config) {
  const std::vector<std::string>& yielding = config.yielding_objections;
  return std::all_of(objections.begin(), objections.end(), [&yielding](const Objection& o) {
    return std::find(yielding.begin(), yielding.end(), o.key) != yielding.end();
  });
}

// First admissible candidate with the largest key (earlier candidates win ties).
template <typename Key>
int argmaxBy(const std::vector<BranchVerdict>& verdicts, Key key) {
  int best = -1;
  for (size_t i = 0; i < verdicts.size(); ++i)
    if (verdicts[i].admissible && (best < 0 || key(verdicts[i]) > key(verdicts[best]))) best = static_cast<int>(i);
  return best;
}

}  // namespace

bool movesOn(const std::vector<BranchVerdict>& verdicts) {
  return std::any_of(verdicts.begin(), verdicts.end(),
                     [](const BranchVerdict& v) { return v.admissible && !v.rotation_only && !v.yielded; });
}

int selectBranch(std::vector<BranchVerdict>& verdicts, const PolicyConfig& config, uint64_t step_seed) {
  std::vector<bool> may_yield(verdicts.size(), false);
  for (size_t i = 0; i < verdicts.size(); ++i) {
    BranchVerdict& v = verdicts[i];
    v.score = config.lambda_cov * v.coverage + config.lambda_prog * v.progress + config.goal_weight * v.goal +
              config.opening_weight * v.opening;
    const std::vector<Objection> objections = objectionsTo(v, config);
    v.reason.clear();
    for (const Objection& o : objections) v.reason += (v.reason.empty() ? "" : ";") + std::string(o.text);
    v.admissible = objections.empty();
    v.yielded = false;
    may_yield[i] = !v.admissible && !v.rotation_only && allYield(objections, config);
  }
  // [ours] No way on (policy.yielding_objections, docs/pockets.md "Objections that give
  // way"): a translation whose every objection may give way is admitted. Its reason is
  // cleared; its flags still say what gave way.
  if (!movesOn(verdicts))
    for (size_t i = 0; i < verdicts.size(); ++i)
      if (may_yield[i]) {
        verdicts[i].reason.clear();
        verdicts[i].admissible = verdicts[i].yielded = true;
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
