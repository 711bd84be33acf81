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
// rejected translation that stops short of the obstacle (clean_prefix.h); the same form
// names the fixed-length short translations and turns ([ours], policy.short_*_frames).
// An in-place turn of any length is "<jq|lq>:<frames>", e.g. "lq:114" = lq's turn held
// for 114 frames (180 degrees right): the turn to the open direction ([ours],
// policy.open_turn). It is also a key string ('j' / 'l' turn, 'q' stands still), read
// as such; its candidate (the branch it runs on in the ROS graph) is jq or lq.
// The goal move ([ours], policy.goal_move; geometry/goal_move.h) is a key string of
// an in-place turn, then a walk, e.g. "l:23,w:41"; like any key string that moves, it
// runs on uw's branch in the ROS graph.
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
// How many leading frames two sequences share (equal motion steps): "uw@32" and "uw"
// 32, "jq" and "jq:114" 57, "uw" and "jq" 0.
size_t sharedFrames(const ActionSequence& a, const ActionSequence& b);
// The paper candidate a name is (a prefix or a turn of): "uw@31" -> "uw", "jq" -> "jq",
// "lq:114" -> "lq"; the branch a key string runs on: "uw" when one of its keys moves
// (w, s, a, d), else "jq" or "lq" by the sign of its net turn ("l:23,w:41" -> "uw",
// "j:3,l:5" -> "lq"). Anything else (not KEYS:FRAMES segments) is returned whole.
std::string baseCandidate(const std::string& name);
// The in-place turn by `yaw_deg` (left positive) at jq / lq's rate: "jq:<frames>" or
// "lq:<frames>", frames = round(|yaw| / (rotate_deg / H)), at least 1.
std::string turnName(double yaw_deg, const Config& config);
// The goal move's key string: the in-place turn of turnName, then `walk_cells` coverage
// cells forward at w's speed (policy.cells_per_d_fwd cells are one forward action of
// H frames): "l:23,w:41"; without the turn when it rounds to no frame ("w:41").
std::string goalMoveName(double turn_deg, double walk_cells, const Config& config);
// A name with what it does, for logs: "lq:114 (turn 180 deg right)", "uw@32 (4.5 m forward)".
std::string describeAction(const std::string& name, const Config& config);

// A candidate name (uw, jw, lw, jq, lq), a candidate prefix (uw@31) or a key string. Speeds: w moves d_fwd/H
// units per frame; j/l turn rotate_deg/H per frame, except inside jw/lw whose turn
// segment turns turn_forward_deg over H frames. Throws InputError naming the string
// for an unknown candidate, key or malformed segment.
ActionSequence makeActionSequence(const std::string& candidate_or_keys, const Config& config);

}  // namespace valerant
