// Coverage/progress scores, argmax selection, failed regions and dead-pocket rewinds
// on hand-built grids and step sequences.
#include <gtest/gtest.h>

#include "unit_grid.h"
#include "valerant/explore/failed_region_memory.h"
#include "valerant/explore/policy.h"
#include "valerant/explore/rewind_controller.h"
#include "valerant/geometry/coverage_grid.h"

#include <cmath>
#include <set>

using namespace valerant;

namespace {

using test::unitGrid;  // the anchor sits at the centre of cell (64, 64)

std::vector<Eigen::Vector3d> line(double x0, double y0, double x1, double y1, int n) {
  std::vector<Eigen::Vector3d> c;
  for (int i = 0; i <= n; ++i)
    c.push_back({x0 + (x1 - x0) * i / n, y0 + (y1 - y0) * i / n, 1.0});
  return c;
}

}  // namespace

TEST(CoverageGrid, CellsAndAnchor) {
  const CoverageGrid g = unitGrid();
  EXPECT_DOUBLE_EQ(g.cellSize(), 1.0);
  Cell c;
  ASSERT_TRUE(g.cellOf({0, 0, 0}, c));
  EXPECT_EQ(c, Cell(64, 64));
  ASSERT_TRUE(g.cellOf({2.4, -1.6, 5}, c));  // height does not matter
  EXPECT_EQ(c, Cell(66, 62));
  EXPECT_FALSE(g.cellOf({100, 0, 0}, c));
}

TEST(CoverageGrid, NewCellsFrontierAndProgress) {
  CoverageGrid g = unitGrid();
  // Committed so far: standing at the origin; floor observed for x in [-2, 3], |y| <= 2.
  g.markVisited({0, 0, 1});
  for (int x = -2; x <= 3; ++x)
    for (int y = -2; y <= 2; ++y) g.markObservedFloor({double(x), double(y), 0});
  // Forward 8 along +X: cells x = 0..8 -> 8 new (the origin is visited): C_new = 8/8.
  // It ends at x = 8, 5 cells beyond the frontier at x = 3: C_front = 1/(1 + 5/8).
  const CoverageTerms fwd = g.score(line(0, 0, 8, 0, 64));
  EXPECT_DOUBLE_EQ(fwd.c_new, 1.0);
  EXPECT_DOUBLE_EQ(fwd.c_front, 1.0 / (1.0 + 5.0 / 8));
  EXPECT_DOUBLE_EQ(fwd.coverage, 1.0 + 0.5 / (1.0 + 5.0 / 8));
  EXPECT_DOUBLE_EQ(fwd.progress, 1.0);
  // Rotation in place: no new cell, ends 3 cells from the frontier, no progress.
  const CoverageTerms rot = g.score(line(0, 0, 0, 0, 10));
  EXPECT_DOUBLE_EQ(rot.c_new, 0.0);
  EXPECT_DOUBLE_EQ(rot.c_front, 1.0 / (1.0 + 2.0 / 8));  // nearest frontier 2 cells away: x = -2 or y = +-2
  EXPECT_DOUBLE_EQ(rot.progress, 0.0);
  // Back over visited ground 4 cells: 4 new cells (x = -1..-4), progress 0.5.
  const CoverageTerms back = g.score(line(0, 0, -4, 0, 32));
  EXPECT_DOUBLE_EQ(back.c_new, 0.5);
  EXPECT_DOUBLE_EQ(back.progress, 0.5);
}

TEST(Policy, ArgmaxOverAdmissibleWithDeterministicTies) {
  PolicyConfig config;
  std::vector<BranchVerdict> v(5);
  const char* names[] = {"uw", "jw", "lw", "jq", "lq"};
  for (int i = 0; i < 5; ++i) v[i].candidate = names[i];
  // uw: C = 1.3, P = 1 -> 6.3 but collides; jw: C = 1.5, P = 0.875 -> 5.875;
  // lw: C = 0.875, P = 1 -> 5.875 (a tie with jw: jw is listed first); jq/lq: 0.4.
  v[0].coverage = 1.3, v[0].progress = 1.0, v[0].collision_depth = true;
  v[1].coverage = 1.5, v[1].progress = 0.875;
  v[2].coverage = 0.875, v[2].progress = 1.0;
  v[3].coverage = 0.4;
  v[4].coverage = 0.4;
  EXPECT_EQ(selectBranch(v, config), 1);
  EXPECT_DOUBLE_EQ(v[0].score, 6.3);
  EXPECT_FALSE(v[0].admissible);
  EXPECT_EQ(v[0].reason, "depth collision");
  EXPECT_EQ(v[1].score, 5.875);  // exact in binary: a true tie
  EXPECT_EQ(v[2].score, 5.875);
  // Everything blocked: a stall.
  for (auto& b : v) b.collision_pc = true;
  v[3].collision_pc = v[4].collision_pc = false;
  v[3].enters_failed = true;
  v[4].slam_lost = true;
  EXPECT_EQ(selectBranch(v, config), -1);
  EXPECT_EQ(v[3].reason, "enters failed region");
  EXPECT_EQ(v[4].reason, "slam lost");
  // A turn where the last translation ended in contact ([ours], collision.turn_contact_points).
  v[4].slam_lost = false;
  v[4].turn_in_contact = true;
  EXPECT_EQ(selectBranch(v, config), -1);
  EXPECT_EQ(v[4].reason, "turn in place while in contact");
  // A translation that ends in contact ([ours], collision.end_clearance).
  v[4].turn_in_contact = false;
  v[4].ends_in_contact = true;
  EXPECT_EQ(selectBranch(v, config), -1);
  EXPECT_EQ(v[4].reason, "ends in contact");
}

// [ours] policy.no_turn_back: after a committed lq (90 degrees right) the jq back scores
// highest (C 0.9 against 0.5 for jq@28, 0.4 for lq; no translation admissible), but a
// turn back is chosen only when nothing else is admissible: jq@28 (index 2). With jq@28
// and lq blocked too, the turn back is all there is and is chosen; it stays admissible.
TEST(Policy, ATurnBackIsChosenOnlyWhenNothingElseIsAdmissible) {
  PolicyConfig config;
  std::vector<BranchVerdict> v(4);
  const char* names[] = {"uw", "jq", "jq@28", "lq"};
  for (int i = 0; i < 4; ++i) v[i].candidate = names[i];
  v[0].collision_pc = true;
  v[1].coverage = 0.9, v[1].turns_back = true;
  v[2].coverage = 0.5;
  v[3].coverage = 0.4;
  EXPECT_EQ(selectBranch(v, config), 2);
  EXPECT_TRUE(v[1].admissible);
  v[2].enters_failed = v[3].enters_failed = true;
  EXPECT_EQ(selectBranch(v, config), 1);
  EXPECT_EQ(v[1].reason, "");
}

// [ours] policy.yielding_objections. Scores (lambda_cov 1, lambda_prog 5): jw 0.3 + 5 * 0.5
// = 2.8 (in F), lw 0.1 + 5 * 0.6 = 3.1 (in F and short unclear), uw@32 5.0 (short unclear
// and a point-cloud collision), jq 0.9 (a turn, admissible). No objection yields: jq.
// F yields: jw, the only translation objected to by F alone (2.8 > 0.9). F and short
// unclear yield: lw (3.1); uw@32's collision never yields. Once uw is admissible (0.2 +
// 5 * 0.1 = 0.7) nothing yields and jq (0.9) wins again, with every reason back.
TEST(Policy, ObjectionsYieldOnlyWhenNoTranslationIsAdmissible) {
  PolicyConfig config;
  std::vector<BranchVerdict> v(5);
  const char* names[] = {"uw", "jw", "lw", "uw@32", "jq"};
  for (int i = 0; i < 5; ++i) v[i].candidate = names[i];
  v[0].collision_pc = true, v[0].coverage = 0.2, v[0].progress = 0.1;
  v[1].enters_failed = true, v[1].coverage = 0.3, v[1].progress = 0.5;
  v[2].enters_failed = v[2].short_unclear = true, v[2].coverage = 0.1, v[2].progress = 0.6;
  v[3].short_unclear = v[3].collision_pc = true, v[3].progress = 1.0;
  v[4].rotation_only = true, v[4].coverage = 0.9;
  EXPECT_EQ(selectBranch(v, config), 4);
  config.yielding_objections = {"enters_failed"};
  EXPECT_EQ(selectBranch(v, config), 1);
  EXPECT_TRUE(v[1].admissible && v[1].yielded);
  EXPECT_EQ(v[1].reason, "");
  EXPECT_TRUE(v[1].enters_failed);  // the flag still says what gave way
  EXPECT_FALSE(movesOn(v));          // a later round may still offer a clear translation
  EXPECT_FALSE(v[2].admissible);
  EXPECT_EQ(v[2].reason, "enters failed region;short action not clear to its end");
  config.yielding_objections = {"enters_failed", "short_unclear"};
  EXPECT_EQ(selectBranch(v, config), 2);
  EXPECT_NEAR(v[2].score, 3.1, 1e-12);
  EXPECT_TRUE(v[1].yielded && v[2].yielded);
  EXPECT_FALSE(v[3].admissible || v[3].yielded);
  EXPECT_EQ(v[3].reason, "point-cloud collision;short action not clear to its end");
  EXPECT_FALSE(v[4].yielded);
  v[0].collision_pc = false;
  EXPECT_EQ(selectBranch(v, config), 4);
  EXPECT_TRUE(movesOn(v));
  EXPECT_FALSE(v[1].admissible || v[1].yielded || v[2].admissible || v[2].yielded);
  EXPECT_EQ(v[1].reason, "enters failed region");
}

// [ours] dead_pocket.ban_rewound_headings: a translation heading into a pocket rewound
// from here is inadmissible, with its reason; the best of the others is chosen.
TEST(Policy, AHeadingRewoundOutOfIsInadmissible) {
  PolicyConfig config;
  std::vector<BranchVerdict> v(2);
  v[0].candidate = "uw", v[0].coverage = 0.9, v[0].rewound_before = true;
  v[1].candidate = "jw", v[1].coverage = 0.2;
  EXPECT_EQ(selectBranch(v, config), 1);
  EXPECT_FALSE(v[0].admissible);
  EXPECT_EQ(v[0].reason, "heads into a pocket rewound from here");
  EXPECT_FALSE(v[0].predictsCollision());  // a memory of the rewinds, not a collision
}

// The verdicts scored as predicted collisions: either test, a turn held back after a
// contact, or a translation ending in contact; a lost track, the failed region or a short action's unclear end are not.
TEST(Policy, PredictedCollisionsAreTheTestsAndTurnsInContact) {
  BranchVerdict v;
  EXPECT_FALSE(v.predictsCollision());
  v.slam_lost = v.enters_failed = v.short_unclear = v.floor_unknown = true;
  EXPECT_FALSE(v.predictsCollision());
  for (bool BranchVerdict::*flag :
       {&BranchVerdict::collision_pc, &BranchVerdict::collision_depth, &BranchVerdict::turn_in_contact,
        &BranchVerdict::ends_in_contact}) {
    BranchVerdict w;
    w.*flag = true;
    EXPECT_TRUE(w.predictsCollision());
  }
}

TEST(Policy, MotionBeyondMaxProgressIsInadmissible) {
  PolicyConfig config;  // max_progress 3
  std::vector<BranchVerdict> v(3);
  // uw reconstructed 10.6 forward actions away (a scale runaway; 5 * 10.6 + 10 = 63):
  // it would win eq. 2 but is inadmissible; jw at 2.9 (score 14.5 + 1 = 15.5) is
  // chosen; exactly 3 is allowed; NaN is not.
  v[0].candidate = "uw", v[0].coverage = 10, v[0].progress = 10.6;
  v[1].candidate = "jw", v[1].coverage = 1, v[1].progress = 2.9;
  v[2].candidate = "lw", v[2].coverage = 0, v[2].progress = 3.0;
  EXPECT_EQ(selectBranch(v, config), 1);
  EXPECT_FALSE(v[0].admissible);
  EXPECT_EQ(v[0].reason, "implausible motion");
  EXPECT_DOUBLE_EQ(v[1].score, 15.5);
  EXPECT_TRUE(v[2].admissible);
  v[2].progress = std::nan("");
  selectBranch(v, config);
  EXPECT_FALSE(v[2].admissible);
  // 0 switches the check off (the paper): uw wins with 63.
  config.max_progress = 0;
  EXPECT_EQ(selectBranch(v, config), 0);
  EXPECT_DOUBLE_EQ(v[0].score, 63.0);
}

TEST(FailedRegionMemory, EnteringIsLeavingTheStartCellIntoF) {
  FailedRegionMemory f;
  f.add({{64, 64}, {65, 64}, {66, 64}});
  EXPECT_TRUE(f.enters({{64, 64}, {65, 64}}, {64, 64}));   // forward into the pocket
  EXPECT_FALSE(f.enters({{64, 64}, {64, 65}}, {64, 64}));  // sideways out of it
  EXPECT_FALSE(f.enters({{64, 64}}, {64, 64}));             // turning on the spot
  // A turn whose reconstructed centres jitter into the neighbouring cell of F: the body
  // does not move, so it enters nothing; the same cells walked do.
  EXPECT_FALSE(f.enters({{64, 64}, {65, 64}}, {64, 64}, true));
  EXPECT_TRUE(f.enters({{64, 64}, {65, 64}}, {64, 64}, false));
}

// [ours] dead_pocket.cross_failed: only where a translation ends counts.
TEST(FailedRegionMemory, EndingInFIsEndingOnTheDiscardedWalk) {
  FailedRegionMemory f;
  f.add({{65, 63}, {65, 64}, {65, 65}});               // a walk across x = 65
  EXPECT_TRUE(f.enters({{64, 64}, {65, 64}, {66, 64}}, {64, 64}));  // crossing it enters F ...
  EXPECT_FALSE(f.endsIn({66, 64}, {64, 64}));          // ... but ends beyond it
  EXPECT_TRUE(f.endsIn({65, 64}, {64, 64}));           // stopping on it
  EXPECT_FALSE(f.endsIn({65, 64}, {65, 64}));          // the start cell never holds the agent
  EXPECT_FALSE(f.endsIn({65, 64}, {64, 64}, true));    // a turn's centre jitters; its body stays
}

// [ours] dead_pocket.free_way_back removes the kept path's cells: only those held count.
TEST(FailedRegionMemory, RemovingCountsOnlyTheCellsItHeld) {
  FailedRegionMemory f;
  f.add({{64, 64}, {65, 64}, {66, 64}});
  EXPECT_EQ(f.remove({{65, 64}, {66, 64}, {70, 70}}), 2u);
  EXPECT_EQ(f.cells(), (std::set<Cell>{{64, 64}}));
  EXPECT_EQ(f.remove({{65, 64}}), 0u);
}

TEST(RewindController, DeadEndRewindsBeforeThePocketAndMarksIt) {
  DeadPocketConfig config;  // the paper: only the anchor's own cell stays free
  RewindController r(config);
  // Step 1 (checkpoint 1): forward (64,64) -> (72,64). Step 2 (checkpoint 2): forward
  // into the dead end, (72,64) -> (75,64). Then three rotations at (75,64).
  r.recordStep(1, {64, 64}, true, false, {{64, 64}, {68, 64}, {72, 64}});
  r.recordStep(2, {72, 64}, true, false, {{72, 64}, {73, 64}, {74, 64}, {75, 64}});
  EXPECT_FALSE(r.check());
  // A rotation or a stall is no anchor: its checkpoint is released at once.
  EXPECT_EQ(r.recordStep(3, {75, 64}, true, true, {{75, 64}}), (std::vector<uint64_t>{3}));
  EXPECT_EQ(r.recordStep(4, {75, 64}, true, true, {{75, 64}}), (std::vector<uint64_t>{4}));
  EXPECT_FALSE(r.check());  // two rotations are no dead pocket yet
  EXPECT_EQ(r.recordStep(5, {75, 64}, false, false, {}), (std::vector<uint64_t>{5}));  // a stall counts too
  const auto d = r.check();
  ASSERT_TRUE(d);
  EXPECT_EQ(d->checkpoint, 2u);  // before walking into the dead end
  EXPECT_EQ(d->discarded_steps, 4);
  EXPECT_EQ(d->failed_cells, (std::set<Cell>{{73, 64}, {74, 64}, {75, 64}}));  // anchor cell kept free
  const auto released = r.apply(*d);
  EXPECT_EQ(released, (std::vector<uint64_t>{2}));  // 3, 4 and 5 went when they were recorded
  EXPECT_EQ(r.rewinds(), 1);
  EXPECT_EQ(r.retained(), (std::vector<uint64_t>{1}));
}

TEST(RewindController, AKnownPocketIsPassedOverToTheAnchorBefore) {
  // Step 1 (checkpoint 1): forward (64,64) -> (68,64). Step 2 (checkpoint 2): a short
  // walk from (68,64) that ends at (69,64). Then three rotations at (69,64).
  auto walk_into_pocket = [](RewindController& r) {
    r.recordStep(1, {64, 64}, true, false, {{64, 64}, {66, 64}, {68, 64}});
    r.recordStep(2, {68, 64}, true, false, {{68, 64}, {69, 64}});
    for (uint64_t c = 3; c <= 5; ++c) r.recordStep(c, {69, 64}, true, true, {{69, 64}});
  };
  const std::set<Cell> f_holds_the_pocket{{69, 64}};
  const auto in_f = [&](const Cell& c) { return f_holds_the_pocket.count(c) > 0; };
  const auto in_empty_f = [](const Cell&) { return false; };
  DeadPocketConfig config;
  config.reach_past_known_pocket = true;
  // F already holds (69,64), all the rewind to anchor 2 would add (its own cell (68,64)
  // stays free): it goes to anchor 1 and adds (66,64), (68,64), (69,64).
  RewindController known(config);
  walk_into_pocket(known);
  const auto d = known.check(in_f);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->checkpoint, 1u);
  EXPECT_EQ(d->reached_past, 1);
  EXPECT_EQ(d->discarded_steps, 5);
  EXPECT_EQ(d->failed_cells, (std::set<Cell>{{66, 64}, {68, 64}, {69, 64}}));
  EXPECT_EQ(known.apply(*d), (std::vector<uint64_t>{1, 2}));
  // A pocket F does not know yet: the most recent anchor, as the paper.
  RewindController fresh(config);
  walk_into_pocket(fresh);
  const auto first = fresh.check(in_empty_f);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->checkpoint, 2u);
  EXPECT_EQ(first->reached_past, 0);
  // Without the option, or without F's cells, the known pocket is rewound to anchor 2.
  RewindController paper{DeadPocketConfig{}};
  walk_into_pocket(paper);
  EXPECT_EQ(paper.check(in_f)->checkpoint, 2u);
  RewindController blind(config);
  walk_into_pocket(blind);
  EXPECT_EQ(blind.check()->checkpoint, 2u);
  // With no anchor before it, the known pocket is rewound to the one there is.
  RewindController alone(config);
  alone.recordStep(2, {68, 64}, true, false, {{68, 64}, {69, 64}});
  for (uint64_t c = 3; c <= 5; ++c) alone.recordStep(c, {69, 64}, true, true, {{69, 64}});
  const auto only = alone.check(in_f);
  ASSERT_TRUE(only);
  EXPECT_EQ(only->checkpoint, 2u);
  EXPECT_EQ(only->reached_past, 0);
}

TEST(RewindController, AWalkThatEndsInItsStartCellCountsAsATurn) {
  // Step 1 (checkpoint 1): forward (64,64) -> (68,64). Step 2 (checkpoint 2): a short
  // walk that ends in its start cell (68,64). Then two rotations at (68,64).
  PocketSignals in_cell;
  in_cell.ended_in_start_cell = true;
  auto walk_in_a_cell = [&](RewindController& r) {
    r.recordStep(1, {64, 64}, true, false, {{64, 64}, {66, 64}, {68, 64}});
    const auto released = r.recordStep(2, {68, 64}, true, false, {{68, 64}}, in_cell);
    for (uint64_t c = 3; c <= 4; ++c) r.recordStep(c, {68, 64}, true, true, {{68, 64}});
    return released;
  };
  // The paper: the walk is a translation, an anchor, and resets the count; two
  // rotations after it are no dead pocket.
  RewindController paper{DeadPocketConfig{}};
  EXPECT_TRUE(walk_in_a_cell(paper).empty());
  EXPECT_FALSE(paper.check());
  EXPECT_EQ(paper.retained(), (std::vector<uint64_t>{1, 2}));
  // With the option the walk counts as the first of three turns: its checkpoint is
  // released at once, and the rewind goes to anchor 1, before the walk, putting the
  // walk's cell into F ((64,64), the anchor's cell, stays free).
  DeadPocketConfig config;
  config.walk_in_cell_is_turn = true;
  RewindController r(config);
  EXPECT_EQ(walk_in_a_cell(r), (std::vector<uint64_t>{2}));
  const auto d = r.check();
  ASSERT_TRUE(d);
  EXPECT_EQ(d->checkpoint, 1u);
  EXPECT_EQ(d->discarded_steps, 4);
  EXPECT_EQ(d->failed_cells, (std::set<Cell>{{66, 64}, {68, 64}}));
  // A walk that leaves its start cell is a translation with the option too.
  RewindController left(config);
  left.recordStep(1, {64, 64}, true, false, {{64, 64}, {66, 64}, {68, 64}});
  EXPECT_TRUE(left.recordStep(2, {68, 64}, true, false, {{68, 64}, {69, 64}}).empty());
  EXPECT_EQ(left.retained(), (std::vector<uint64_t>{1, 2}));
}

TEST(RewindController, AnchorNeighbourhoodStaysOutOfF) {
  // The same dead end with radius 1: (73,64) borders the anchor cell (72,64) and stays
  // free, the pocket's cells (74,64) and (75,64) are marked.
  DeadPocketConfig config;
  config.anchor_free_cells = 1;
  RewindController r(config);
  r.recordStep(1, {64, 64}, true, false, {{64, 64}, {68, 64}, {72, 64}});
  r.recordStep(2, {72, 64}, true, false, {{72, 64}, {73, 64}, {74, 64}, {75, 64}});
  for (uint64_t c = 3; c <= 5; ++c) r.recordStep(c, {75, 64}, true, true, {{75, 64}});
  const auto d = r.check();
  ASSERT_TRUE(d);
  EXPECT_EQ(d->failed_cells, (std::set<Cell>{{74, 64}, {75, 64}}));
}

TEST(RewindController, AtMostTwoRewindsAndOnlyThreeAnchorsKept) {
  DeadPocketConfig config;
  RewindController r(config);
  uint64_t id = 1;
  std::vector<uint64_t> released;
  for (int i = 0; i < 5; ++i) {  // five forward steps: only the last three are anchors
    auto rel = r.recordStep(id, {64 + i, 64}, true, false, {{64 + i, 64}, {65 + i, 64}});
    released.insert(released.end(), rel.begin(), rel.end());
    ++id;
  }
  EXPECT_EQ(released, (std::vector<uint64_t>{1, 2}));
  EXPECT_EQ(r.retained(), (std::vector<uint64_t>{3, 4, 5}));
  for (int rewind = 0; rewind < 3; ++rewind) {
    for (int k = 0; k < 3; ++k) r.recordStep(id++, {69, 64}, true, true, {{69, 64}});
    const auto d = r.check();
    if (rewind < 2) {
      ASSERT_TRUE(d) << "rewind " << rewind;
      EXPECT_EQ(d->checkpoint, rewind == 0 ? 5u : 4u);  // each rewind reaches further back
      const auto rel = r.apply(*d);
      // The second rewind is the last: anchor 3 goes with it, as no rewind can follow.
      const std::vector<uint64_t> expected = rewind == 0 ? std::vector<uint64_t>{5} : std::vector<uint64_t>{4, 3};
      EXPECT_EQ(rel, expected);
    } else {
      EXPECT_FALSE(d) << "a third rewind was allowed";
    }
  }
  EXPECT_EQ(r.rewinds(), 2);
  EXPECT_FALSE(r.canRewindLater());
  EXPECT_TRUE(r.retained().empty());
  // Every later step's checkpoint, a translation's too, is released when recorded.
  EXPECT_EQ(r.recordStep(id, {69, 64}, true, false, {{69, 64}, {70, 64}}), (std::vector<uint64_t>{id}));
  EXPECT_TRUE(r.retained().empty());
}

TEST(RewindController, ALongTurnInPlaceHoldsOnlyTheAnchors) {
  // Two translations, then 50 turns in place (every translation rejected): before, each
  // turn's checkpoint (a copy of the SLAM, floor and grid state) stayed held until the
  // next translation, so memory grew with every turn. Now the turns hold nothing.
  DeadPocketConfig config;
  config.rotation_only_steps = 1000;  // no dead pocket declared during the turns
  RewindController r(config);
  r.recordStep(1, {64, 64}, true, false, {{64, 64}, {65, 64}});
  r.recordStep(2, {65, 64}, true, false, {{65, 64}, {66, 64}});
  for (uint64_t id = 3; id < 53; ++id)
    EXPECT_EQ(r.recordStep(id, {66, 64}, true, true, {{66, 64}}), (std::vector<uint64_t>{id}));
  EXPECT_EQ(r.retained(), (std::vector<uint64_t>{1, 2}));
  EXPECT_TRUE(r.canRewindLater());
}

TEST(RewindController, CanRewindLaterNeedsAnAnchor) {
  DeadPocketConfig config;
  RewindController r(config);
  EXPECT_FALSE(r.canRewindLater());  // nothing committed yet
  r.recordStep(1, {64, 64}, true, true, {{64, 64}});
  r.recordStep(2, {64, 64}, false, false, {});
  EXPECT_FALSE(r.canRewindLater());  // a rotation and a stall are no anchors
  r.recordStep(3, {64, 64}, true, false, {{64, 64}, {65, 64}});
  EXPECT_TRUE(r.canRewindLater());
  config.enabled = false;
  RewindController off(config);
  off.recordStep(1, {64, 64}, true, false, {{64, 64}, {65, 64}});
  EXPECT_FALSE(off.canRewindLater());
}

// [ours] trapped(): a dead pocket is declared and no rewind can follow it, either because
// a rewind consumed the last anchor (rewinds left, none held: the 150-step runs' end,
// docs/pockets.md) or because the rewinds are spent. A pocket with an anchor held is
// rewound, not trapped, and fewer turns than rotation_only_steps declare nothing.
TEST(RewindController, APocketNoRewindCanFollowIsTrapped) {
  DeadPocketConfig config;
  config.max_rewinds = 25;
  RewindController r(config);
  r.recordStep(1, {64, 64}, true, false, {{64, 64}, {65, 64}});  // the only anchor
  for (uint64_t id = 2; id <= 4; ++id) r.recordStep(id, {65, 64}, true, true, {{65, 64}});
  EXPECT_FALSE(r.trapped());  // a pocket, but anchor 1 is held
  const auto d = r.check();
  ASSERT_TRUE(d);
  EXPECT_EQ(d->checkpoint, 1u);
  r.apply(*d);
  EXPECT_FALSE(r.canRewindLater());  // 24 rewinds left, no anchor
  r.recordStep(5, {64, 64}, true, true, {{64, 64}});
  r.recordStep(6, {64, 64}, true, true, {{64, 64}});
  EXPECT_FALSE(r.trapped());  // two turns: no pocket yet
  r.recordStep(7, {64, 64}, false, false, {});  // a stall counts as in the paper's rule
  EXPECT_TRUE(r.trapped());
  EXPECT_FALSE(r.check());
  r.recordStep(8, {64, 64}, true, false, {{64, 64}, {63, 64}});  // out: a new anchor
  EXPECT_FALSE(r.trapped());
  EXPECT_TRUE(r.canRewindLater());
  // Spent rewinds: the paper's two, then three turns.
  RewindController spent(DeadPocketConfig{});
  uint64_t id = 1;
  for (int rewind = 0; rewind < 2; ++rewind) {
    spent.recordStep(id++, {64, 64}, true, false, {{64, 64}, {65, 64}});
    for (int k = 0; k < 3; ++k) spent.recordStep(id++, {65, 64}, true, true, {{65, 64}});
    spent.apply(*spent.check());
  }
  for (int k = 0; k < 3; ++k) spent.recordStep(id++, {65, 64}, true, true, {{65, 64}});
  EXPECT_TRUE(spent.trapped());
}

TEST(RewindController, DisabledNeverRewinds) {
  DeadPocketConfig config;
  config.enabled = false;
  RewindController r(config);
  // Nothing can be rewound to, so every checkpoint is released when its step is recorded.
  EXPECT_EQ(r.recordStep(1, {64, 64}, true, false, {{64, 64}, {65, 64}}), (std::vector<uint64_t>{1}));
  for (uint64_t id = 2; id < 6; ++id)
    EXPECT_EQ(r.recordStep(id, {65, 64}, true, true, {{65, 64}}), (std::vector<uint64_t>{id}));
  EXPECT_FALSE(r.check());
  EXPECT_TRUE(r.retained().empty());
}

// [ours] Stagnant pockets (rewind_controller.h), K = 3 steps under 5 new floor cells.
// Step 1 walks (64,64) -> (66,64) seeing 40 new cells; step 2 drops off a ledge into
// (67,64)-(68,64) (12 new cells: the lower room); steps 3-8 walk and turn there, each
// seeing 0-5 new cells: a translation and a turn in turn, never three rotations in a
// row. Checkpoints kept 1: held are the most recent anchor, the drop anchor (2) and the
// one anchor before it (1); anchor 3, between the drop and the most recent, is released
// when 5 comes. After step 8 (the third stagnant step) the rewind goes to 2, before the
// drop, and F takes every cell from the drop on: (67,64), (68,64), (69,64), (70,64); the
// drop's start cell (66,64) stays free. Anchor 1 is still held after it: three turns in
// place then rewind there, as the paper's rule would.
TEST(RewindController, StagnantPocketRewindsBeforeTheLatestDrop) {
  DeadPocketConfig config;
  config.checkpoints_kept = 1;
  config.max_rewinds = 5;
  config.stagnant_steps = 3;
  config.stagnant_cells = 5;
  RewindController r(config);
  EXPECT_EQ(r.recordStep(1, {64, 64}, true, false, {{64, 64}, {65, 64}, {66, 64}}, {false, 40}),
            (std::vector<uint64_t>{}));
  // The drop: anchor 2 is the most recent anchor and the drop anchor; 1 stays, before it.
  EXPECT_EQ(r.recordStep(2, {66, 64}, true, false, {{66, 64}, {67, 64}, {68, 64}}, {true, 12}),
            (std::vector<uint64_t>{}));
  // A stagnant walk: 3 is the most recent anchor, 2 is held as the drop anchor.
  EXPECT_EQ(r.recordStep(3, {68, 64}, true, false, {{68, 64}, {69, 64}}, {false, 4}), (std::vector<uint64_t>{}));
  EXPECT_EQ(r.retained(), (std::vector<uint64_t>{1, 2, 3}));
  EXPECT_EQ(r.recordStep(4, {69, 64}, true, true, {{69, 64}}, {false, 0}), (std::vector<uint64_t>{4}));
  EXPECT_FALSE(r.check());  // two stagnant steps
  // A walk that sees 5 new cells gains: the count starts again.
  EXPECT_EQ(r.recordStep(5, {69, 64}, true, false, {{69, 64}, {70, 64}}, {false, 5}),
            (std::vector<uint64_t>{3}));  // anchor 3, between the drop anchor and 5, is released
  EXPECT_EQ(r.retained(), (std::vector<uint64_t>{1, 2, 5}));
  EXPECT_EQ(r.stagnantSteps(), 0);
  r.recordStep(6, {70, 64}, true, true, {{70, 64}}, {false, 1});
  r.recordStep(7, {70, 64}, true, false, {{70, 64}, {69, 64}}, {false, 0});
  EXPECT_FALSE(r.check());
  r.recordStep(8, {69, 64}, true, true, {{69, 64}}, {false, 2});
  EXPECT_EQ(r.stalledSteps(), 1);  // no dead pocket by the paper's rule
  const auto d = r.check();
  ASSERT_TRUE(d);
  EXPECT_TRUE(d->stagnant);
  EXPECT_EQ(d->checkpoint, 2u);
  EXPECT_EQ(d->discarded_steps, 7);  // steps 2 to 8
  EXPECT_EQ(d->failed_cells, (std::set<Cell>{{67, 64}, {68, 64}, {69, 64}, {70, 64}}));
  // The held checkpoints from the drop anchor on are consumed: 2 and 7 (5 went when 7 came).
  EXPECT_EQ(r.apply(*d), (std::vector<uint64_t>{2, 7}));
  EXPECT_EQ(r.retained(), (std::vector<uint64_t>{1}));
  EXPECT_EQ(r.stagnantSteps(), 0);
  // Back at the drop's start the agent turns in place three times: a dead pocket by the
  // paper's rule, rewound to anchor 1 (the drop path is in F already).
  EXPECT_TRUE(r.canRewindLater());
  for (uint64_t id = 9; id <= 11; ++id) r.recordStep(id, {66, 64}, true, true, {{66, 64}}, {false, 20});
  const auto back = r.check();
  ASSERT_TRUE(back);
  EXPECT_FALSE(back->stagnant);
  EXPECT_EQ(back->checkpoint, 1u);
  EXPECT_EQ(back->discarded_steps, 4);  // step 1 and the three turns
  EXPECT_EQ(back->failed_cells, (std::set<Cell>{{65, 64}, {66, 64}}));
}

// A drop whose start stood in contact (N_occ committed points inside the body there, as
// where a graze left the camera in a brush) is no drop anchor: the stagnant rewind goes
// to the most recent anchor instead, and only the checkpoints_kept most recent are held.
TEST(RewindController, ADropThatStartedInContactIsNoDropAnchor) {
  DeadPocketConfig config;
  config.checkpoints_kept = 1;
  config.stagnant_steps = 2;
  config.stagnant_cells = 5;
  RewindController r(config);
  r.recordStep(1, {64, 64}, true, false, {{64, 64}, {65, 64}}, {false, 40});
  EXPECT_EQ(r.recordStep(2, {65, 64}, true, false, {{65, 64}, {66, 64}}, {true, 12, true}),
            (std::vector<uint64_t>{1}));
  EXPECT_EQ(r.recordStep(3, {66, 64}, true, false, {{66, 64}, {67, 64}}, {false, 0}), (std::vector<uint64_t>{2}));
  EXPECT_EQ(r.retained(), (std::vector<uint64_t>{3}));
  r.recordStep(4, {67, 64}, true, true, {{67, 64}}, {false, 0});
  const auto d = r.check();
  ASSERT_TRUE(d);
  EXPECT_TRUE(d->stagnant);
  EXPECT_EQ(d->checkpoint, 3u);
  EXPECT_EQ(d->discarded_steps, 2);
}

// Without a drop the stagnant rule rewinds to the most recent anchor, as the paper's; and
// off (the default) it never fires and no drop anchor is held.
TEST(RewindController, StagnantPocketWithoutADropAndOff) {
  DeadPocketConfig config;
  config.stagnant_steps = 2;
  RewindController r(config);
  r.recordStep(1, {64, 64}, true, false, {{64, 64}, {65, 64}}, {false, 0});
  r.recordStep(2, {65, 64}, true, false, {{65, 64}, {66, 64}}, {false, 0});
  const auto d = r.check();
  ASSERT_TRUE(d);
  EXPECT_TRUE(d->stagnant);
  EXPECT_EQ(d->checkpoint, 2u);
  EXPECT_EQ(d->failed_cells, (std::set<Cell>{{66, 64}}));
  DeadPocketConfig paper;
  paper.checkpoints_kept = 1;
  RewindController off(paper);
  off.recordStep(1, {64, 64}, true, false, {{64, 64}, {65, 64}}, {true, 0});
  EXPECT_EQ(off.recordStep(2, {65, 64}, true, false, {{65, 64}, {66, 64}}, {false, 0}), (std::vector<uint64_t>{1}));
  for (uint64_t id = 3; id < 20; ++id) off.recordStep(id, {66, 64}, true, false, {{66, 64}, {67, 64}}, {false, 0});
  EXPECT_FALSE(off.check());
  EXPECT_EQ(off.stagnantSteps(), 0);
}

TEST(Policy, BaselinesChooseAmongTheAdmissible) {
  std::vector<BranchVerdict> v(5);
  const char* names[] = {"uw", "jw", "lw", "jq", "lq"};
  for (int i = 0; i < 5; ++i) v[i].candidate = names[i];
  v[3].rotation_only = v[4].rotation_only = true;
  v[1].c_front = 0.5, v[2].c_front = 0.5, v[2].coverage = 1.0;  // lw: same C_front, more coverage
  PolicyConfig config;
  config.kind = "forward";
  EXPECT_EQ(selectBranch(v, config), 0);  // uw while it is admissible
  v[0].collision_pc = true;
  EXPECT_EQ(selectBranch(v, config), 3);  // then the first rotation
  config.kind = "frontier";
  EXPECT_EQ(selectBranch(v, config), 2);
  config.kind = "random";
  std::set<int> seen;
  for (uint64_t seed = 0; seed < 64; ++seed) {
    const int c = selectBranch(v, config, seed);
    EXPECT_NE(c, 0);  // never the colliding one
    EXPECT_EQ(c, selectBranch(v, config, seed));  // the same seed, the same choice
    seen.insert(c);
  }
  EXPECT_EQ(seen.size(), 4u);
}

TEST(Policy, WholeLevelTermsJoinTheScore) {
  // eq. 2 plus goal_weight G + opening_weight O ([ours]): with lambda_cov 1, lambda_prog 5,
  // goal_weight 2 and opening_weight 0.5,
  //   uw@32: C 0.5, P 0.5, G -0.25 -> 0.5 + 2.5 - 0.5 = 2.5
  //   jw@32: C 0.5, P 0.4, G  0.25 -> 0.5 + 2.0 + 0.5 = 3.0 (the goal outweighs the progress)
  //   jq:114: C 0.25, O 1 -> 0.25 + 0.5 = 0.75;  jq: C 0.25, O 0.125 -> 0.3125
  std::vector<BranchVerdict> v(4);
  v[0].candidate = "uw@32", v[0].coverage = 0.5, v[0].progress = 0.5, v[0].goal = -0.25;
  v[1].candidate = "jw@32", v[1].coverage = 0.5, v[1].progress = 0.4, v[1].goal = 0.25;
  v[2].candidate = "jq:114", v[2].coverage = 0.25, v[2].opening = 1.0, v[2].rotation_only = true;
  v[3].candidate = "jq", v[3].coverage = 0.25, v[3].opening = 0.125, v[3].rotation_only = true;
  PolicyConfig config;
  config.goal_weight = 2.0;
  config.opening_weight = 0.5;
  EXPECT_EQ(selectBranch(v, config), 1);
  EXPECT_DOUBLE_EQ(v[0].score, 2.5);
  EXPECT_DOUBLE_EQ(v[1].score, 3.0);
  EXPECT_DOUBLE_EQ(v[2].score, 0.75);
  EXPECT_DOUBLE_EQ(v[3].score, 0.3125);
  v[0].collision_pc = v[1].collision_pc = true;
  EXPECT_EQ(selectBranch(v, config), 2);  // turns rank by where they face
  // The paper's weights (0) ignore both terms: uw@32 3.0 against jw@32 2.5.
  PolicyConfig paper;
  paper.goal_weight = paper.opening_weight = 0;
  EXPECT_EQ(selectBranch(v, paper), 2);  // (uw, jw still colliding) jq:114 first of equal turns
  v[0].collision_pc = v[1].collision_pc = false;
  EXPECT_EQ(selectBranch(v, paper), 0);
  EXPECT_DOUBLE_EQ(v[0].score, 3.0);
  v[0].short_unclear = true;  // uw@32 stops short of its end's clearance: out
  EXPECT_EQ(selectBranch(v, paper), 1);
  EXPECT_EQ(v[0].reason, "short action not clear to its end");
}
