#pragma once
// Per-frame camera motion commanded to a world model, in the key vocabulary of
// Matrix-Game-style action-conditioned video models: w/s forward/back, a/d strafe,
// j/l yaw left/right, i/k pitch up/down. A key string is a comma-separated list of
// KEYS:FRAMES segments, e.g. "jw:57,w:40" = yaw left while moving forward for 57
// frames, then forward for 40. The five paper candidates (eq. 3) are key strings
// built from the rollout config:
//   uw = "w:H"      jw = "jw:H,w:T"   lw = "lw:H,w:T"   jq = "j:H"   lq = "l:H"
// A candidate's clean prefix ([ours], collision.prefix_commits) is named
// "<candidate>@<frames>", e.g. "uw@31" = the first 31 frames of uw: the part of a
// rejected translation that stops short of the obstacle (clean_prefix.h).
#include <string>
#include <vector>

#include "valerant/config/config.h"

namespace valerant {

struct MotionStep {
  double forward_units = 0;  // along the current heading (game units)
  double strafe_units = 0;   // to the right of the heading
  double yaw_deg = 0;        // positive turns left (counter-clockwise seen from above)
  double pitch_deg = 0;      // positive looks down, as in Quake
};

struct ActionSequence {
  std::string name;  // candidate name or the key string it came from
  std::vector<MotionStep> steps;
  bool rotationOnly() const;     // no frame translates
  double totalYawDeg() const;
  double totalForwardUnits() const;
};

// The paper's candidates, in the paper's order (eq. 3).
const std::vector<std::string>& candidateNames();

// "uw@31" for the first 31 frames of uw (makeActionSequence checks the count).
std::string prefixName(const std::string& candidate, int frames);
// The paper candidate a name is (a prefix of): "uw@31" -> "uw", "jq" -> "jq".
std::string baseCandidate(const std::string& name);

// A candidate name (uw, jw, lw, jq, lq), a candidate prefix (uw@31) or a key string. Speeds: w moves d_fwd/H
// units per frame; j/l turn rotate_deg/H per frame, except inside jw/lw whose turn
// segment turns turn_forward_deg over H frames. Throws InputError naming the string
// for an unknown candidate, key or malformed segment.
ActionSequence makeActionSequence(const std::string& candidate_or_keys, const Config& config);

}  // namespace valerant
