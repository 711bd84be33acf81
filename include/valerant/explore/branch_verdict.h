#pragma once
// Everything the policy knows about one candidate at one step: the collision tests,
// the score terms and why it was rejected. Mirrors msg/BranchVerdict.msg.
#include <string>
#include <vector>

namespace valerant {

struct BranchVerdict {
  std::string candidate;
  bool rotation_only = false;
  bool collision_pc = false;
  bool collision_depth = false;
  // [ours] A turn in place while in contact: where the last committed translation ended
  // in contact (collision.turn_contact_points) or with committed points inside the body
  // at its start (collision.turn_start_points; episode.h): the camera may stand inside a brush.
  bool turn_in_contact = false;
  // [ours] A translation whose last frame has N_occ points within collision.end_clearance
  // of the body axis (branch_check.h): it would leave the agent standing in contact.
  bool ends_in_contact = false;
  int occupied_max = 0;
  double min_near_ratio = 0;
  // [ours] Diagnostics of eq. 6 (docs/inside_brush.md): count_i at rho for every frame
  // (empty for a branch without a known floor), so a graze can be read back from the
  // record; and the committed points already inside the body cylinder at the start,
  // which eq. 6 leaves out (branch_check.h).
  std::vector<int> body_counts;
  int start_occupied = 0;
  // [ours] Points left out of eq. 6 because the branch's frames saw past them
  // (collision.see_through_frames, free_space_evidence.h).
  int see_through_points = 0;
  bool slam_lost = false;
  bool floor_unknown = false;  // a translation judged without any reliable floor
  bool enters_failed = false;
  // Leading frames clear by collision.prefix_margin of every fired test, SLAM loss and
  // the prefix_clearance cylinder (clean_prefix.h): all frames when none of them
  // happened, 0 when no prefix advances far enough.
  int prefix_frames = 0;
  double c_new = 0, c_front = 0, coverage = 0, progress = 0;
  // [ours] whole-level terms (docs/whole_level.md): G, the approach to the nearest
  // reachable frontier (frontier_distance.h), and O, the opening ahead of an in-place
  // turn's final heading (open_direction.h; 0 for a translation).
  double goal = 0, opening = 0;
  // [ours] A short translation (policy.short_translation_frames) or goal move
  // (policy.goal_move) whose clean prefix is shorter than itself: such actions end in
  // front of walls by design, and the paper's
  // tests let a rollout's last frames come close (s_min(l) shrinks to 0 at its end), so
  // they are held to the clean prefix's margins (clean_prefix.h) to their last frame.
  bool short_unclear = false;
  // [ours] A turn in place that undoes the last committed step's turn in place
  // (policy.no_turn_back; turn_back.h): ranked below every other admissible candidate.
  bool turns_back = false;
  // [ours] A translation heading, from a state a rewind went back to, where a walk that led
  // into the pocket went (dead_pocket.ban_rewound_headings; rewound_headings.h).
  bool rewound_before = false;
  double score = 0;
  bool admissible = false;
  // [ours] Admitted although objected to: no translation was admissible and every
  // objection is one policy.yielding_objections lets give way (policy.h).
  bool yielded = false;
  std::string reason;  // "" when admissible

  // Rejected as colliding: the outcome scored against the engine's truth (verdict
  // precision and recall) and drawn red. A turn after a contact counts: it is held back
  // for fear of solid.
  bool predictsCollision() const { return collision_pc || collision_depth || turn_in_contact || ends_in_contact; }
};

}  // namespace valerant
