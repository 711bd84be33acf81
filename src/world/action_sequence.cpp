#include "valerant/world/action_sequence.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <optional>
#include <sstream>
#include <utility>

#include "valerant/common/error.h"
#include "valerant/common/whole_integer.h"
#include "valerant/world/quake3/units.h"

namespace valerant {

bool ActionSequence::rotationOnly() const {
  for (const auto& s : steps)
    if (s.forward_units != 0 || s.strafe_units != 0) return false;
  return true;
}

double ActionSequence::totalYawDeg() const {
  double sum = 0;
  for (const auto& s : steps) sum += s.yaw_deg;
  return sum;
}

double ActionSequence::totalForwardUnits() const {
  double sum = 0;
  for (const auto& s : steps) sum += s.forward_units;
  return sum;
}

const std::vector<std::string>& candidateNames() {
  static const std::vector<std::string> names = {"uw", "jw", "lw", "jq", "lq"};
  return names;
}

namespace {

std::string candidateKeys(const std::string& name, const RolloutConfig& r) {
  const std::string h = std::to_string(r.horizon_frames);
  const std::string tail = r.turn_forward_frames > 0 ? ",w:" + std::to_string(r.turn_forward_frames) : "";
  if (name == "uw") return "w:" + h;
  if (name == "jw") return "jw:" + h + tail;
  if (name == "lw") return "lw:" + h + tail;
  if (name == "jq") return "j:" + h;
  if (name == "lq") return "l:" + h;
  return "";
}

// Splits "uw@31" into ("uw", 31); a name without '@' is returned whole with -1.
std::pair<std::string, int> splitPrefix(const std::string& name) {
  const size_t at = name.find('@');
  if (at == std::string::npos) return {name, -1};
  const std::string what = "action '" + name + "'";
  const std::string base = name.substr(0, at);
  const auto& names = candidateNames();
  if (std::find(names.begin(), names.end(), base) == names.end())
    throw InputError(what, "'" + base + "' is not a candidate (a prefix is <uw|jw|lw|jq|lq>@<frames>)");
  const std::optional<int> frames = wholeInteger<int>(name.substr(at + 1));
  if (!frames) throw InputError(what, "prefix frame count is not an integer");
  return {base, *frames};
}

// "jq:114" -> "jq": a rotation candidate's key string with a frame count of its own.
std::optional<std::string> turnCandidate(const std::string& name) {
  for (const char* turn : {"jq", "lq"}) {
    const std::string head = std::string(turn) + ":";
    if (name.rfind(head, 0) == 0 && wholeInteger<int>(name.substr(head.size()))) return std::string(turn);
  }
  return std::nullopt;
}

// The branch of a key string (see baseCandidate), or nothing when `keys` is not made
// of KEYS:FRAMES segments; the keys themselves are checked by makeActionSequence.
std::optional<std::string> keyStringBranch(const std::string& keys) {
  std::stringstream in(keys);
  std::string segment;
  bool moves = false;
  long net_turn = 0;
  while (std::getline(in, segment, ',')) {
    const size_t colon = segment.find(':');
    if (colon == std::string::npos || colon == 0) return std::nullopt;
    const std::optional<int> frames = wholeInteger<int>(segment.substr(colon + 1));
    if (!frames) return std::nullopt;
    for (const char k : segment.substr(0, colon)) {
      if (k == 'w' || k == 's' || k == 'a' || k == 'd') moves = true;
      if (k == 'j') net_turn += *frames;
      if (k == 'l') net_turn -= *frames;
    }
  }
  if (moves) return std::string("uw");
  return std::string(net_turn >= 0 ? "jq" : "lq");
}

}  // namespace

std::string baseCandidate(const std::string& name) {
  if (const auto turn = turnCandidate(name)) return *turn;
  const auto [base, frames] = splitPrefix(name);
  if (frames >= 0) return base;
  const auto& names = candidateNames();
  if (std::find(names.begin(), names.end(), name) != names.end()) return name;
  if (const auto branch = keyStringBranch(name)) return *branch;
  return name;
}

std::string turnName(double yaw_deg, const Config& config) {
  const double rate = config.rollout.rotate_deg / config.rollout.horizon_frames;
  const int frames = std::max(1, static_cast<int>(std::lround(std::abs(yaw_deg) / rate)));
  return std::string(yaw_deg >= 0 ? "jq" : "lq") + ":" + std::to_string(frames);
}

std::string goalMoveName(double turn_deg, double walk_cells, const Config& config) {
  const int walk_frames = std::max(
      1, static_cast<int>(std::lround(walk_cells / config.policy.cells_per_d_fwd * config.rollout.horizon_frames)));
  const std::string walk = "w:" + std::to_string(walk_frames);
  const double rate = config.rollout.rotate_deg / config.rollout.horizon_frames;
  const long turn_frames = std::lround(std::abs(turn_deg) / rate);
  if (turn_frames == 0) return walk;
  return std::string(turn_deg >= 0 ? "j:" : "l:") + std::to_string(turn_frames) + "," + walk;
}

std::string describeAction(const std::string& name, const Config& config) {
  const ActionSequence seq = makeActionSequence(name, config);
  const double yaw = seq.totalYawDeg();
  const double metres = seq.totalForwardUnits() / quake3::kUnitsPerMetre;
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out << name << " (";
  if (std::abs(yaw) >= 0.5) out << "turn " << std::setprecision(0) << std::abs(yaw) << " deg " << (yaw > 0 ? "left" : "right");
  if (std::abs(yaw) >= 0.5 && metres != 0) out << ", ";
  if (metres != 0) out << std::setprecision(1) << metres << " m forward";
  if (std::abs(yaw) < 0.5 && metres == 0) out << "no motion";
  out << ")";
  return out.str();
}

std::string prefixName(const std::string& candidate, int frames) { return candidate + "@" + std::to_string(frames); }

size_t sharedFrames(const ActionSequence& a, const ActionSequence& b) {
  size_t n = 0;
  while (n < a.steps.size() && n < b.steps.size()) {
    const MotionStep &x = a.steps[n], &y = b.steps[n];
    if (x.forward_units != y.forward_units || x.strafe_units != y.strafe_units || x.yaw_deg != y.yaw_deg ||
        x.pitch_deg != y.pitch_deg)
      break;
    ++n;
  }
  return n;
}


ActionSequence makeActionSequence(const std::string& name, const Config& config) {
  const auto [candidate_or_keys, prefix_frames] = splitPrefix(name);
  const RolloutConfig& r = config.rollout;
  std::string keys = candidateKeys(candidate_or_keys, r);
  const bool is_candidate = !keys.empty();
  if (!is_candidate) keys = candidate_or_keys;
  const std::string what = "action '" + name + "'";
  if (keys.empty()) throw InputError(what, "empty action string");

  const double speed = config.world.d_fwd_units / r.horizon_frames;
  const double rotate_rate = r.rotate_deg / r.horizon_frames;
  // Inside jw / lw the turn segment turns turn_forward_deg, not rotate_deg.
  const double turn_forward_rate = r.turn_forward_deg / r.horizon_frames;

  ActionSequence seq;
  seq.name = name;
  std::stringstream in(keys);
  std::string segment;
  while (std::getline(in, segment, ',')) {
    const size_t colon = segment.find(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == segment.size())
      throw InputError(what, "segment '" + segment +
                                 "' is not KEYS:FRAMES (unknown candidate? use uw, jw, lw, jq, lq)");
    const std::string held = segment.substr(0, colon);
    const std::optional<int> parsed = wholeInteger<int>(segment.substr(colon + 1));
    if (!parsed) throw InputError(what, "frame count in '" + segment + "' is not an integer");
    const int frames = *parsed;
    if (frames < 1 || frames > 100000) throw InputError(what, "frame count in '" + segment + "' out of [1, 100000]");

    const bool moves = held.find_first_of("wsad") != std::string::npos;
    const double yaw_rate = (is_candidate && moves) ? turn_forward_rate : rotate_rate;
    MotionStep step;
    for (char k : held) {
      switch (k) {
        case 'w': step.forward_units += speed; break;
        case 's': step.forward_units -= speed; break;
        case 'd': step.strafe_units += speed; break;
        case 'a': step.strafe_units -= speed; break;
        case 'j': step.yaw_deg += yaw_rate; break;
        case 'l': step.yaw_deg -= yaw_rate; break;
        case 'k': step.pitch_deg += rotate_rate; break;
        case 'i': step.pitch_deg -= rotate_rate; break;
        case 'u': break;  // Matrix-Game's "no camera motion" key
        case 'q': break;  // Matrix-Game's "no movement" key
        default:
          throw InputError(what, std::string("unknown key '") + k + "' (keys: w s a d j l i k u q)");
      }
    }
    seq.steps.insert(seq.steps.end(), frames, step);
  }
  if (prefix_frames >= 0) {
    const int full_frames = static_cast<int>(seq.steps.size());
    if (prefix_frames < 1 || prefix_frames >= full_frames)
      throw InputError(what, "prefix of " + std::to_string(prefix_frames) + " frames is outside [1, " +
                                 std::to_string(full_frames - 1) + "] (" + candidate_or_keys + " has " +
                                 std::to_string(full_frames) + ")");
    seq.steps.resize(prefix_frames);
  }
  return seq;
}

}  // namespace valerant
