#include "valerant/explore/episode_json.h"

#include <algorithm>

namespace valerant {

nlohmann::json toJson(const BranchVerdict& v) {
  return {{"candidate", v.candidate},     {"rotation_only", v.rotation_only},
          {"collision_pc", v.collision_pc}, {"collision_depth", v.collision_depth},
          {"turn_in_contact", v.turn_in_contact}, {"ends_in_contact", v.ends_in_contact},
          {"occupied_max", v.occupied_max}, {"min_near_ratio", std::isfinite(v.min_near_ratio) ? v.min_near_ratio : -1.0},
          {"slam_lost", v.slam_lost},       {"floor_unknown", v.floor_unknown},
          {"enters_failed", v.enters_failed}, {"prefix_frames", v.prefix_frames},
          {"c_new", v.c_new},               {"c_front", v.c_front},
          {"coverage", v.coverage},         {"progress", v.progress},
          {"goal", v.goal},                 {"opening", v.opening},
          {"short_unclear", v.short_unclear}, {"turns_back", v.turns_back},
          {"rewound_before", v.rewound_before},
          {"body_counts", v.body_counts},   {"start_occupied", v.start_occupied}, {"see_through_points", v.see_through_points},
          {"score", v.score},               {"admissible", v.admissible},
          {"yielded", v.yielded},           {"reason", v.reason}};
}

nlohmann::json toJson(const StageSeconds& s) {
  return {{"render", s.render}, {"slam", s.slam},     {"floor", s.floor},
          {"collision", s.collision}, {"policy", s.policy}, {"fusion", s.fusion}};
}

nlohmann::json toJson(const StepRecord& r) {
  nlohmann::json verdicts = nlohmann::json::array();
  int in_solid_frames = 0;
  for (const auto& c : r.candidates) {
    nlohmann::json v = toJson(c.verdict);
    if (!c.truth.empty()) {
      int solid = 0;
      double highest_floor = c.truth.front().floor_z;
      for (const auto& f : c.truth) {
        solid += f.in_solid;
        highest_floor = std::max(highest_floor, f.floor_z);
      }
      v["truth_in_solid_frames"] = solid;
      // Frame by frame, beside body_counts: where a graze entered and what followed.
      std::string camera(c.truth.size(), '0'), hull(c.truth.size(), '0');
      for (size_t i = 0; i < c.truth.size(); ++i) {
        if (c.truth[i].in_solid) camera[i] = '1';
        if (c.truth[i].hull_in_solid) hull[i] = '1';
      }
      v["truth_in_solid_mask"] = camera;
      v["truth_hull_in_solid_mask"] = hull;
      // How far up the true path climbs (game units; a stair is 16, a step at most 18):
      // tells a rejected climb from a rejected wall in the record.
      v["truth_rise_units"] = highest_floor - c.truth.front().floor_z;
      if (&c - r.candidates.data() == r.chosen) in_solid_frames = solid;
    }
    verdicts.push_back(v);
  }
  return {{"step", r.step},
          {"checkpoint", r.checkpoint},
          {"chosen", r.chosen >= 0 ? r.candidates[r.chosen].verdict.candidate : ""},
          {"stall", r.chosen < 0},
          {"verdicts", verdicts},
          {"committed_in_solid_frames", in_solid_frames},
          {"rewind", r.rewind},
          {"rewind_stagnant", r.rewind_stagnant},
          {"rewind_to", r.rewind_to},
          {"discarded_steps", r.discarded_steps},
          {"failed_forgotten", r.failed_forgotten},
          {"way_back_freed", r.way_back_freed},
          {"rewind_reached_past", r.rewind_reached_past},
          {"goal_frontiers", r.goal_frontiers},
          {"goal_distance", r.goal_distance},
          {"goal_distance_without_failed", r.goal_distance_without_failed},
          {"new_floor_cells", r.new_floor_cells},
          {"drop", r.drop},
          {"ended_in_start_cell", r.ended_in_start_cell},
          {"seconds", toJson(r.seconds)},
          {"wall_seconds", r.wall_seconds}};
}

}  // namespace valerant
