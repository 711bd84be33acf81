#pragma once
// [ours] A turn in place that undoes the one before it (policy.no_turn_back). An agent
// whose translations are all rejected turns in place, and the best turn from the new
// heading is often the one back: in the 150-step visual runs the agent alternated `jq`
// and `lq` for its last 84 steps (oa_dm1 spawn 0) or 140 (spawn 2), judging the same two
// headings again and again and never the others. A turn by `turn_deg` (left positive)
// right after a committed turn in place by `last_turn_deg` turns back when the two have
// opposite signs and the heading it ends at lies within `min_turn_deg` of the one the
// last turn started from: |last_turn_deg + turn_deg| < min_turn_deg. Episode uses half
// of jw / lw's turn (22.5 degrees), the same bound under which an open turn is no new
// direction.
namespace valerant {

bool turnsBack(double last_turn_deg, double turn_deg, double min_turn_deg);

}  // namespace valerant
