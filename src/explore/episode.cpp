#include "valerant/explore/episode.h"

#include <algorithm>
#include <chrono>
#include <cstdint>

#include "valerant/common/error.h"
#include "valerant/explore/kept_truth.h"
#include "valerant/explore/local_branch_pipeline.h"
#include "valerant/explore/turn_back.h"
#include "valerant/geometry/frontier_distance.h"
#include "valerant/geometry/goal_move.h"
#include "valerant/geometry/open_direction.h"

namespace valerant {
namespace {

constexpr int kOpenDirectionRays = 72;  // every 5 degrees: finer than the grid resolves a few metres out

// Camera centres of a candidate: the committed start, then one per frame.
std::vector<Eigen::Vector3d> centresOf(const Eigen::Vector3d& start, const std::vector<Eigen::Isometry3d>& poses) {
  std::vector<Eigen::Vector3d> centres{start};
  for (const auto& pose : poses) centres.push_back(pose.translation());
  return centres;
}

// A candidate's walk: its last camera centre less its first (centresOf).
Eigen::Vector3d walkOf(const std::vector<Eigen::Vector3d>& centres) { return centres.back() - centres.front(); }

}  // namespace

Episode::Episode(WorldModel& world, const Config& config)
    : Episode(world, std::make_unique<LocalBranchPipeline>(world.intrinsics(), config),
              std::make_unique<PolicyBranchSelector>(config.policy), nullptr, nullptr, config) {}

Episode::Episode(WorldModel& world, BranchPipeline& pipeline, BranchSelector& selector, const Config& config)
    : Episode(world, nullptr, nullptr, &pipeline, &selector, config) {}

Episode::Episode(WorldModel& world, std::unique_ptr<BranchPipeline> own_pipeline,
                 std::unique_ptr<BranchSelector> own_selector, BranchPipeline* pipeline, BranchSelector* selector,
                 const Config& config)
    : world_(world),
      own_pipeline_(std::move(own_pipeline)),
      own_selector_(std::move(own_selector)),
      pipeline_(pipeline ? *pipeline : *own_pipeline_),
      selector_(selector ? *selector : *own_selector_),
      config_(config),
      d_fwd_normalised_(config.world.d_fwd_units / config.world.eye_height_units),
      map_(config.map, config.collision),
      rewinder_(config.dead_pocket),
      rewound_(config.rollout.turn_forward_deg / 4) {
  if (config.loop_closure.enabled)  // the oracle SLAM is metric: no scale to correct
    loop_closure_.emplace(config.loop_closure, world.intrinsics(), config.slam.backend != "oracle");
  const Rollout context = world_.context();
  const BranchResult start = pipeline_.start(context);
  if (start.poses.empty()) throw InputError("world model context", "no frame was tracked (empty context)");
  fuseKnown(start);
  trajectory_ = start.poses;
  appendCommittedTruth(truth_, std::vector<FrameTruth>(context.truth.begin(),
                                                        context.truth.begin() + std::min(context.truth.size(), start.poses.size())));
  anchorGrid(start.floor_reliable);
  if (loop_closure_) loop_closure_->commit(start, 0, anchor_floor_, map_, trajectory_);
}

void Episode::anchorGrid(bool reliable_floor) {
  // The grid is anchored at the start pose on the floor plane; until a reliable floor
  // exists the anchor is provisional and is redone once one is found.
  const Eigen::Isometry3d& start = trajectory_.front();
  anchor_floor_ = pipeline_.floorAt(start);
  anchor_heading_ = start.linear().col(2);
  anchored_on_reliable_floor_ = reliable_floor;
  rebuildGrid();
}

void Episode::rebuildGrid() {
  grid_.emplace(config_.policy, anchor_floor_, anchor_heading_, d_fwd_normalised_);
  for (const auto& pose : trajectory_) grid_->markVisited(pose.translation());
  for (const auto& kf : map_.keyframes()) markGrid(*kf);
}

void Episode::markGrid(const FusedKeyframe& keyframe) {
  // Floor points mark observed floor; points at body height (the collision test's band)
  // mark obstacles, which only the whole-level terms read (coverage_grid.h).
  // With the surface layer every point below the band's top (not overhead) also marks
  // the height of what stands in its cell, and with carving the ray to it marks the cells
  // it crossed as free where it crossed them.
  const CollisionConfig& band = config_.collision;
  const Eigen::Vector3d eye = keyframe.camera_to_map.translation();
  for (const auto& p : keyframe.points) {
    const Eigen::Vector3d position = p.position.cast<double>();
    if (std::abs(p.h) < band.height_low)
      grid_->markObservedFloor(position);
    else if (p.h <= band.height_high)
      grid_->markObstaclePoint(position);
    if (p.h <= band.height_high) {
      grid_->markSurfacePoint(position);
      grid_->markSurfaceRay(eye, position, p.h, band.height_low);
    }
  }
}

size_t Episode::fuseKnown(const BranchResult& result) {
  // A keyframe without a known floor has no heights: fusing it would mark made-up
  // floor and obstacles in the map and the coverage grid.
  size_t fused = 0;
  for (size_t i = 0; i < result.keyframes.size(); ++i) {
    if (!result.keyframe_floors[i].known) continue;
    map_.fuse(result.keyframes[i], result.keyframe_floors[i]);
    ++fused;
  }
  return fused;
}

cv::Mat Episode::currentView() const {
  const Rollout context = world_.context();
  return context.frames.empty() ? cv::Mat() : context.frames.back();
}

bool Episode::finished() const {
  return stuck_ || committed_steps_ >= config_.policy.budget_steps ||
         steps_ >= static_cast<std::int64_t>(config_.policy.step_cap_factor) * config_.policy.budget_steps;
}

StepRecord Episode::step() {
  const auto step_start = std::chrono::steady_clock::now();
  StepRecord record;
  record.step = ++steps_;
  record.checkpoint = world_.checkpoint();
  pipeline_.checkpoint(record.checkpoint);
  saved_.emplace(record.checkpoint, Saved{*grid_, map_.marker(), trajectory_.size(), committed_steps_,
                                          loop_closure_, contact_points_, last_turn_deg_});
  Cell start_cell{-1, -1};
  grid_->cellOf(trajectory_.back().translation(), start_cell);
  recordGoal(start_cell, record);

  Candidates judged;
  std::vector<std::string> first_round = candidateNames();
  const auto t_move = std::chrono::steady_clock::now();
  const std::optional<std::string> goal_move = goalMoveAction();
  record.seconds.policy += secondsSince(t_move);
  if (goal_move && std::find(first_round.begin(), first_round.end(), *goal_move) == first_round.end())
    first_round.push_back(*goal_move);
  // Later rounds (all but the clean prefixes known now) judge shorter or longer
  // versions of these candidates: their branches are kept where those begin alike.
  const std::vector<std::vector<std::string>> rounds = roomActionRounds();
  auto namesAfter = [&rounds](size_t round) {
    std::vector<std::string> names;
    for (size_t r = round; r < rounds.size(); ++r) names.insert(names.end(), rounds[r].begin(), rounds[r].end());
    return names;
  };
  judge(first_round, namesAfter(0), start_cell, record, judged);
  holdToClearEnd(judged, candidateNames().size());
  const uint64_t step_seed = (uint64_t{config_.world.seed} << 32) + record.step;
  auto select = [&] {
    const auto t = std::chrono::steady_clock::now();
    record.chosen = selector_.select(judged.verdicts, step_seed);
    record.seconds.policy += secondsSince(t);
  };
  select();
  const std::vector<std::string> prefixes = cleanPrefixes(judged);
  if (!prefixes.empty()) {
    judge(prefixes, namesAfter(0), start_cell, record, judged);
    select();
  }
  for (size_t r = 0; r < rounds.size(); ++r) {  // [ours], docs/whole_level.md
    if (movesOn(judged.verdicts)) break;
    std::vector<std::string> names;
    for (const std::string& name : rounds[r])
      if (std::find(judged.names.begin(), judged.names.end(), name) == judged.names.end()) names.push_back(name);
    if (names.empty()) continue;
    const size_t first_new = judged.verdicts.size();
    judge(names, namesAfter(r + 1), start_cell, record, judged);
    holdToClearEnd(judged, first_new);
    select();
  }
  const auto& results = judged.results;
  const auto& centres = judged.centres;
  const auto& verdicts = judged.verdicts;
  for (size_t i = 0; i < results.size(); ++i) record.candidates.push_back({verdicts[i], centres[i], withoutDepth(results[i].rollout.truth)});

  std::set<Cell> cells;
  bool rotation_only = false;
  PocketSignals signals;
  if (record.chosen >= 0) {
    rotation_only = verdicts[record.chosen].rotation_only;
    Cell cell;
    bool last_in_grid = false;  // after the loop: whether the last camera centre lies in the grid, in `cell`
    for (const auto& c : centres[record.chosen])
      if ((last_in_grid = grid_->cellOf(c, cell))) cells.insert(cell);
    signals.ended_in_start_cell = !rotation_only && last_in_grid && cell == start_cell;
    const size_t start_frame = trajectory_.size() - 1, observed_before = grid_->observedCells();
    const auto t = std::chrono::steady_clock::now();
    commit(results[record.chosen], centres[record.chosen]);
    record.seconds.fusion += secondsSince(t);
    // After the commit, in its grid: a first reliable floor re-anchors the grid and a
    // loop closure corrects the poses, the start's too.
    signals.new_floor_cells = static_cast<int>(std::max(grid_->observedCells(), observed_before) - observed_before);
    const double fall = grid_->heightOf(trajectory_[start_frame].translation()) -
                        grid_->heightOf(trajectory_.back().translation());
    signals.drop = !rotation_only && fall >= config_.dead_pocket.drop_height;
    // Every candidate starts at the same pose; eq. 6 leaves out the committed points
    // already inside the body there and counts them in start_occupied.
    for (const BranchVerdict& v : verdicts)
      signals.start_in_contact |= v.start_occupied >= config_.collision.n_occ;
  }
  record.new_floor_cells = signals.new_floor_cells;
  record.drop = signals.drop;
  record.ended_in_start_cell = signals.ended_in_start_cell;
  release(rewinder_.recordStep(record.checkpoint, start_cell, record.chosen >= 0, rotation_only, cells, signals));
  const auto in_failed = [this](const Cell& c) { return failed_.contains(c); };
  if (const auto decision = rewinder_.check(in_failed)) rewind(*decision, record);
  // [ours] No rewind can follow this pocket, or this stall: the cells earlier rewinds
  // walled off may be all that holds the agent (docs/pockets.md), so F is forgotten and
  // the next step judges its candidates without it; only a stall that forgot nothing is
  // final.
  const bool stall_without_way_back = record.chosen < 0 && !record.rewind && !rewinder_.canRewindLater();
  if (config_.dead_pocket.forget_failed_when_trapped && (rewinder_.trapped() || stall_without_way_back))
    record.failed_forgotten = static_cast<int>(failed_.forget());
  stuck_ = stall_without_way_back && record.failed_forgotten == 0;
  record.map_keyframes = map_.marker();
  record.committed_steps = committed_steps_;
  record.wall_seconds = secondsSince(step_start);
  history_.push_back(record);
  return record;
}

void Episode::judge(const std::vector<std::string>& names, const std::vector<std::string>& later,
                    const Cell& start_cell, StepRecord& record, Candidates& out) {
  std::vector<ActionSequence> later_sequences;
  for (const std::string& name : later) later_sequences.push_back(makeActionSequence(name, config_));
  // Rendering needs the world's single GL context, so rollouts are made one after the
  // other; the pipeline starts each one's reconstruction as soon as it exists.
  std::vector<std::future<BranchResult>> pending;
  for (const std::string& name : names) {
    out.names.push_back(name);
    const ActionSequence seq = makeActionSequence(name, config_);
    std::vector<size_t> keep_after;
    for (const ActionSequence& other : later_sequences)
      if (const size_t shared = sharedFrames(seq, other); shared > 0) keep_after.push_back(shared);
    const auto t = std::chrono::steady_clock::now();
    Rollout rollout = world_.rollout(seq);
    record.seconds.render += secondsSince(t);
    pending.push_back(pipeline_.evaluate(std::move(rollout), seq.rotationOnly(), std::move(keep_after)));
  }
  const Eigen::Vector3d start_centre = trajectory_.back().translation();
  const auto t_goal = std::chrono::steady_clock::now();
  const std::set<Cell> blocked = blockedFrom(start_cell);
  const FrontierDistance goal = goalFrom(start_cell);
  record.seconds.policy += secondsSince(t_goal);
  for (auto& f : pending) {
    out.results.push_back(f.get());
    const BranchResult& result = out.results.back();
    record.seconds += result.seconds;
    const auto t = std::chrono::steady_clock::now();
    out.centres.push_back(centresOf(start_centre, loop_closure_ ? loop_closure_->toMap(result.poses) : result.poses));
    BranchVerdict v = result.verdict;
    const CoverageTerms terms = grid_->score(out.centres.back());
    v.c_new = terms.c_new;
    v.c_front = terms.c_front;
    v.coverage = terms.coverage;
    v.progress = terms.progress;
    Cell end_cell{-1, -1};
    grid_->cellOf(out.centres.back().back(), end_cell);
    v.enters_failed = config_.dead_pocket.cross_failed ? failed_.endsIn(end_cell, start_cell, v.rotation_only)
                                                       : failed_.enters(terms.cells, start_cell, v.rotation_only);
    const int contact = config_.collision.turn_contact_points, start = config_.collision.turn_start_points;
    v.turn_in_contact = v.rotation_only && ((contact > 0 && contact_points_ >= contact) ||
                                            (start > 0 && v.start_occupied >= start));
    v.turns_back = config_.policy.no_turn_back && v.rotation_only && last_turn_deg_ &&
                   turnsBack(*last_turn_deg_, makeActionSequence(v.candidate, config_).totalYawDeg(),
                             config_.rollout.turn_forward_deg / 2);
    v.rewound_before = config_.dead_pocket.ban_rewound_headings && !v.rotation_only &&
                       rewound_.barred(committed_steps_, walkOf(out.centres.back()), *grid_);
    v.goal = goal.goalTerm(start_cell, end_cell);
    v.opening = v.rotation_only && !result.poses.empty()
                    ? opening(*grid_, blocked, start_cell, floorAngle(*grid_, result.poses.back().linear().col(2)))
                    : 0.0;
    out.verdicts.push_back(v);
    record.seconds.policy += secondsSince(t);
  }
}

void Episode::recordGoal(const Cell& start, StepRecord& record) const {
  const auto t = std::chrono::steady_clock::now();
  auto distance = [&](const FrontierDistance& goal) {
    const double d = goal.at(start);
    return d == FrontierDistance::kUnreachable ? -1.0 : d;
  };
  const FrontierDistance goal = goalFrom(start);
  record.goal_frontiers = goal.goalFrontierCells();
  record.goal_distance = distance(goal);
  record.goal_distance_without_failed = failed_.cells().empty() ? record.goal_distance
                                                                 : distance(FrontierDistance(*grid_, {}));
  record.seconds.policy += secondsSince(t);
}

std::set<Cell> Episode::blockedFrom(const Cell& start) const {
  if (config_.dead_pocket.cross_failed) return {};
  std::set<Cell> blocked = failed_.cells();
  blocked.erase(start);  // F never holds the agent in place (failed_region_memory.h)
  return blocked;
}

FrontierDistance Episode::goalFrom(const Cell& start) const {
  if (config_.dead_pocket.cross_failed) return FrontierDistance(*grid_, {}, failed_.cells());
  return FrontierDistance(*grid_, blockedFrom(start));
}

std::optional<double> Episode::openTurnDeg() const {
  Cell here;
  const Eigen::Isometry3d& pose = trajectory_.back();
  if (!grid_->cellOf(pose.translation(), here)) return std::nullopt;
  const double heading = floorAngle(*grid_, pose.linear().col(2));
  const std::set<Cell> blocked = blockedFrom(here);
  // uw heads within half of jw / lw's turn already: a smaller turn is no new direction.
  const double min_turn = config_.rollout.turn_forward_deg / 2;
  // Toward the goal (frontier_distance.h) where it lies off the heading ...
  const FrontierDistance goal = goalFrom(here);
  if (const auto waypoint = goal.waypoint(here, grid_->cellsPerForwardAction())) {
    const double turn = turnDeg(heading, cellAngle(here, *waypoint));
    if (std::abs(turn) >= min_turn) return turn;
  }
  // ... else to the longest free ray (open_direction.h).
  if (const auto open = openDirection(*grid_, blocked, here, heading, kOpenDirectionRays, min_turn))
    return open->turn_deg;
  return std::nullopt;
}

std::optional<std::string> Episode::goalMoveAction() const {
  if (!config_.policy.goal_move) return std::nullopt;
  const Eigen::Isometry3d& pose = trajectory_.back();
  Cell here;
  if (!grid_->cellOf(pose.translation(), here)) return std::nullopt;
  const std::set<Cell> blocked = blockedFrom(here);
  const FrontierDistance goal(*grid_, blocked);
  const auto move = goalMove(*grid_, blocked, goal, grid_->cellCoordinates(pose.translation()),
                             floorAngle(*grid_, pose.linear().col(2)), grid_->cellsPerForwardAction());
  if (!move) return std::nullopt;
  return goalMoveName(move->turn_deg, move->walk_cells, config_);
}

void Episode::holdToClearEnd(Candidates& judged, size_t first) {
  for (size_t i = first; i < judged.verdicts.size(); ++i) {
    BranchVerdict& v = judged.verdicts[i];
    v.short_unclear = !v.rotation_only && v.prefix_frames < static_cast<int>(judged.results[i].poses.size());
  }
}

std::vector<std::vector<std::string>> Episode::roomActionRounds() const {
  const PolicyConfig& p = config_.policy;
  std::vector<std::vector<std::string>> rounds;
  for (const int frames : p.short_translation_frames)
    rounds.push_back({prefixName("uw", frames), prefixName("jw", frames), prefixName("lw", frames)});
  std::vector<std::string> turns;
  for (const int frames : p.short_turn_frames) {
    turns.push_back(prefixName("jq", frames));
    turns.push_back(prefixName("lq", frames));
  }
  if (p.open_turn)
    if (const auto turn = openTurnDeg()) turns.push_back(turnName(*turn, config_));
  if (!turns.empty()) rounds.push_back(turns);
  return rounds;
}

std::vector<std::string> Episode::cleanPrefixes(const Candidates& judged) const {
  if (!config_.collision.prefix_commits) return {};
  if (movesOn(judged.verdicts)) return {};  // the paper's own candidates move on
  std::vector<std::string> names;
  const auto& paper = candidateNames();
  for (size_t i = 0; i < judged.verdicts.size(); ++i) {
    const BranchVerdict& v = judged.verdicts[i];
    if (std::find(paper.begin(), paper.end(), v.candidate) == paper.end()) continue;  // the goal move has none
    const int frames = static_cast<int>(judged.results[i].poses.size());
    if (!v.rotation_only && v.prefix_frames > 0 && v.prefix_frames < frames)
      names.push_back(prefixName(v.candidate, v.prefix_frames));
  }
  return names;
}

void Episode::commit(const BranchResult& chosen, const std::vector<Eigen::Vector3d>& centres) {
  world_.commit(chosen.rollout);
  pipeline_.commit(chosen);
  const size_t fused = fuseKnown(chosen);
  trajectory_.insert(trajectory_.end(), chosen.poses.begin(), chosen.poses.end());
  appendCommittedTruth(truth_, chosen.rollout.truth);
  const std::vector<int>& counts = chosen.verdict.body_counts;
  if (!chosen.verdict.rotation_only) contact_points_ = counts.empty() ? 0 : counts.back();
  last_turn_deg_ = chosen.verdict.rotation_only
                       ? std::optional<double>(makeActionSequence(chosen.verdict.candidate, config_).totalYawDeg())
                       : std::nullopt;
  // Maps the new poses and keyframes into the corrected frame; a closure moves older ones too.
  const bool closed = loop_closure_ && loop_closure_->commit(chosen, committed_steps_ + 1, anchor_floor_, map_, trajectory_);
  ++committed_steps_;
  if (!anchored_on_reliable_floor_ && chosen.floor_reliable) {
    anchorGrid(true);
    return;
  }
  if (closed) {
    rebuildGrid();
    return;
  }
  for (const auto& c : centres) grid_->markVisited(c);
  for (size_t i = map_.marker() - fused; i < map_.marker(); ++i) markGrid(*map_.keyframes()[i]);
}

void Episode::rewind(const RewindDecision& decision, StepRecord& record) {
  world_.restore(decision.checkpoint);
  pipeline_.restore(decision.checkpoint);
  const Saved& s = saved_.at(decision.checkpoint);
  if (!config_.dead_pocket.keep_map) {  // [ours] else what the discarded steps observed stays
    grid_ = s.grid;
    map_.truncate(s.map_marker);
  }
  trajectory_.resize(s.trajectory_size);
  if (truth_.size() > s.trajectory_size) truth_.resize(s.trajectory_size);
  committed_steps_ = s.committed_steps;
  contact_points_ = s.contact_points;
  last_turn_deg_ = s.last_turn_deg;
  if (loop_closure_) {  // closures made after the checkpoint are undone
    LoopClosure left = std::move(*loop_closure_);
    loop_closure_ = s.loop_closure;
    if (config_.dead_pocket.keep_map) loop_closure_->keepKeyframesOf(left);
    loop_closure_->restoreInto(map_, trajectory_);
    // The kept grid marked cells where the undone corrections had put them.
    if (config_.dead_pocket.keep_map && left.corrections() != loop_closure_->corrections()) rebuildGrid();
  }
  failed_.add(decision.failed_cells);
  if (config_.dead_pocket.ban_rewound_headings) {
    // The step that started from the anchor committed the walk into the pocket.
    const auto first = std::find_if(history_.begin(), history_.end(),
                                    [&](const StepRecord& r) { return r.checkpoint == decision.checkpoint; });
    if (first != history_.end() && first->chosen >= 0)
      rewound_.rewoundTo(committed_steps_, walkOf(first->candidates[first->chosen].centres));
  }
  if (config_.dead_pocket.free_way_back) {  // [ours] the way the agent came in stays a way out
    std::set<Cell> kept;
    for (const Eigen::Isometry3d& pose : trajectory_) {
      Cell cell;
      if (grid_->cellOf(pose.translation(), cell)) kept.insert(cell);
    }
    record.way_back_freed = static_cast<int>(failed_.remove(kept));
  }
  record.rewind = true;
  record.rewind_stagnant = decision.stagnant;
  record.rewind_to = decision.checkpoint;
  record.discarded_steps = decision.discarded_steps;
  record.rewind_reached_past = decision.reached_past;
  release(rewinder_.apply(decision));
}

void Episode::release(const std::vector<uint64_t>& checkpoints) {
  for (uint64_t id : checkpoints) {
    world_.dropCheckpoint(id);
    pipeline_.drop(id);
    saved_.erase(id);
  }
}

void Episode::runUntilDone(const std::function<void(const StepRecord&)>& on_step, const std::atomic<bool>* stop) {
  while (!finished() && !(stop && stop->load())) {
    const StepRecord r = step();
    if (on_step) on_step(r);
  }
}

}  // namespace valerant
