// Ground truth of an episode that never translates: a spawn in a small room on oa_dm4
// where every forward candidate (8 m) walks into a wall, so the agent only rotates.
// Positions cannot fit a Sim(3) then; the first pose and the floor tie the map to the
// world instead. With the oracle SLAM (map units are metres, camera 50/32 m above the
// floor) the tie's scale must come out near 1, and the floor seen while turning
// must count as observed. Full 320x240 frames: smaller keyframe clouds hold too few
// floor points for a reliable floor, and without one nothing is fused or measured.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <set>

#include "brush_world.h"
#include "openarena_data.h"
#include "valerant/eval/episode_truth.h"
#include "valerant/eval/live_coverage.h"
#include "valerant/world/quake3/quake3_world.h"

using namespace valerant;
using valerant::test::boxBrush;

TEST(EpisodeTruth, RotationOnlyEpisodeIsTiedToTheWorldByTheFloor) {
  VALERANT_REQUIRE_OPENARENA();
  Config config;
  config.world.spawn = 0;
  config.policy.budget_steps = 2;
  config.slam.backend = "oracle";
  // Every full translation collides here; a clean prefix or a short translation would move.
  config.collision.prefix_commits = false;
  config.policy.short_translation_frames.clear();
  auto map = quake3::loadQuake3Map("oa_dm4", config.world.patch_level);
  quake3::Quake3World world(map, config);
  Episode episode(world, config);
  episode.runUntilDone(nullptr);
  for (const auto& pose : episode.trajectory())  // precondition: rotations in place only
    ASSERT_TRUE(pose.translation().isApprox(episode.trajectory().front().translation(), 1e-9));

  const auto reachable = quake3::floodFillReachableFloor(*map->collision, world.spawnPoints()[0].origin);
  const EpisodeTruth truth = evaluateEpisodeTruth(episode, reachable);
  EXPECT_FALSE(truth.aligned);
  ASSERT_TRUE(truth.floor_aligned);
  // No path to fit, so no ATE (report.json writes null; a grid's mean leaves it out).
  EXPECT_TRUE(std::isnan(truth.ate_percent));
  EXPECT_TRUE(std::isnan(truth.alignment_rmse_m));
  // The estimated floor lies within a few centimetres of the true one (RANSAC on the
  // lower envelope of the keyframe clouds): scale 1 within 5%.
  EXPECT_NEAR(truth.alignment_scale, 1.0, 0.05);
  // The oracle map frame is the BSP frame in metres: no rotation, and the first camera
  // lands on its true centre whatever the scale.
  EXPECT_TRUE(truth.map_to_world_metres.rotation.isApprox(Eigen::Matrix3d::Identity(), 1e-9));
  const Eigen::Vector3d first = episode.trajectory().front().translation();
  EXPECT_TRUE(truth.map_to_world_metres.apply(first).isApprox(first, 1e-9));
  EXPECT_GT(truth.observed_reachable_m2, 10.0);
  // The oracle map is the true depth at the same stride, so it observes what its frames
  // had in view, within the floor tie's scale (5 %) and the estimated floor's band.
  EXPECT_GT(truth.in_view_reachable_m2, 10.0);
  EXPECT_NEAR(truth.observed_reachable_m2, truth.in_view_reachable_m2, 0.05 * truth.in_view_reachable_m2);
  // The progress lines' live count gives the same figure from the same alignment, and
  // counts nothing again while the map stays as it is.
  LiveCoverage live(reachable);
  EXPECT_DOUBLE_EQ(live.update(episode), truth.observed_reachable_percent);
  EXPECT_DOUBLE_EQ(live.update(episode), truth.observed_reachable_percent);
  EXPECT_EQ(live.refits(), 1);
}

namespace {

// A candidate of a hand-made history: one frame per entry of `in_solid` (true: the
// player hull is inside solid there), and the figures its collision tests reported.
CandidateRecord candidate(std::vector<bool> in_solid, const std::string& name = "", int occupied_max = 0,
                          double min_near_ratio = 0) {
  CandidateRecord c;
  c.verdict.candidate = name;
  c.verdict.occupied_max = occupied_max;
  c.verdict.min_near_ratio = min_near_ratio;
  for (bool s : in_solid) c.truth.push_back({Eigen::Isometry3d::Identity(), cv::Mat(), s, 0.0});
  return c;
}

}  // namespace

// Hand-made history: step 1 committed 3 frames, 2 in solid; step 2 stalled (its
// candidates' in-solid frames were never committed); step 3 committed 1 in-solid frame
// of 2; step 4 rewound and committed nothing. 3 in-solid frames were committed.
TEST(EpisodeTruth, CommittedInSolidFramesCountOnlyChosenCandidates) {
  std::vector<StepRecord> history(4);
  history[0].candidates = {candidate({false, false, false}), candidate({false, true, true})};
  history[0].chosen = 1;
  history[1].candidates = {candidate({true, true}), candidate({true})};
  history[2].candidates = {candidate({true, false})};
  history[2].chosen = 0;
  history[3].rewind = true;
  EXPECT_EQ(committedInSolidFrames(history), 3);
  EXPECT_EQ(committedInSolidFrames({}), 0);
}

// The same kind of history: step 2 committed "jw@20" with its 3rd and 4th frames in
// solid, 12 points in its body cylinder and a central depth of 4.6 camera heights;
// step 1 committed a clean "uw"; step 3 stalled with in-solid candidates.
TEST(EpisodeTruth, PenetrationEventsNameTheCommittedStepAndWhatTheTestsSaw) {
  std::vector<StepRecord> history(3);
  history[0].step = 1;
  history[0].candidates = {candidate({false, false}, "uw", 3, 2.0)};
  history[0].chosen = 0;
  history[1].step = 2;
  history[1].candidates = {candidate({true}, "uw", 400, 0.1), candidate({false, false, true, true}, "jw@20", 12, 4.6)};
  history[1].chosen = 1;
  history[2].step = 3;
  history[2].candidates = {candidate({true, true}, "lw", 50, 0.2)};
  const std::vector<PenetrationEvent> events = penetrationEvents(history);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].step, 2);
  EXPECT_EQ(events[0].candidate, "jw@20");
  EXPECT_EQ(events[0].frames, 2);
  EXPECT_EQ(events[0].first_frame, 2);
  EXPECT_EQ(events[0].occupied_max, 12);
  EXPECT_DOUBLE_EQ(events[0].min_near_ratio, 4.6);
  EXPECT_TRUE(penetrationEvents({}).empty());
}

namespace {

// A hand-built world: a floor (top z = 0) over x, y in [-512, 512]; block A at x in
// [100, 200], |y| <= 50, 128 high; block B at x in [-420, -380], |y| <= 20, 64 high. The
// world model's bounds are x, y in [-512, 512], z in [-16, 256]. Its BSP tree has one
// node splitting at x = -256: x >= -256 is leaf 0 (cluster 0, the level), x < -256
// leaf 1 (cluster -1, the void behind an outer wall).
quake3::CollisionModel playableBrushWorld() {
  quake3::PlayableWorld world;
  world.bounds = Eigen::AlignedBox3f(Eigen::Vector3f(-512, -512, -16), Eigen::Vector3f(512, 512, 256));
  world.planes = {{Eigen::Vector3f::UnitX(), -256.f}};
  quake3::BspNode node;
  node.plane = 0;
  node.children = {-1, -2};
  node.mins = node.maxs = Eigen::Vector3i::Zero();  // unused by lookups
  world.nodes = {node};
  world.leaf_clusters = {0, -1};
  return quake3::CollisionModel({boxBrush({-512, -512, -16}, {512, 512, 0}), boxBrush({100, -50, 0}, {200, 50, 128}),
                                 boxBrush({-420, -20, 0}, {-380, 20, 64})},
                                world);
}

// The ground truth of a camera standing on the floor at (x, y), as the engine world
// marks each frame it renders (Quake3World::renderClean).
FrameTruth truthAt(const quake3::CameraKinematics& k, double x, double y) {
  quake3::CameraState s;
  s.xy = {x, y};
  FrameTruth t;
  t.hull_in_solid = k.hullInSolid(s);
  t.hull_in_clip_only = k.hullInClipOnly(s);
  t.outside_world = k.outsideWorld(s);
  t.in_solid = k.inSolid(s);
  return t;
}

}  // namespace

// The player hull spans |x|, |y| <= 15 around the camera and z in [0, 56] above the
// floor; its centre is 28 above the floor. Worked out by hand for each pose:
//   (0, 0)      open floor, centre in leaf 0                  -> neither
//   (150, 0)    hull x in [135, 165] inside block A           -> in solid
//   (600, 0)    centre x = 600 beyond the bounds (512)        -> outside the world
//   (-300, 0)   centre in leaf 1 (no cluster), hull over floor -> outside the world
//   (-400, 0)   inside block B, and in leaf 1                  -> both
// A world without a playable extent (brushes only) flags only the hull.
TEST(EpisodeTruth, PosesInSolidAndOutsideTheWorldArePenetrations) {
  const quake3::CollisionModel model = playableBrushWorld();
  const quake3::CameraKinematics k(model, 50, 1024);
  const std::vector<FrameTruth> frames = {truthAt(k, 0, 0), truthAt(k, 150, 0), truthAt(k, 600, 0),
                                          truthAt(k, -300, 0), truthAt(k, -400, 0)};
  const std::vector<std::array<bool, 3>> expected = {
      // in_solid (the union), hull_in_solid, outside_world
      {false, false, false}, {true, true, false}, {true, false, true}, {true, false, true}, {true, true, true}};
  for (size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(frames[i].in_solid, expected[i][0]) << "pose " << i;
    EXPECT_EQ(frames[i].hull_in_solid, expected[i][1]) << "pose " << i;
    EXPECT_EQ(frames[i].outside_world, expected[i][2]) << "pose " << i;
  }
  EXPECT_EQ(k.hullCentre(quake3::CameraState{}), Eigen::Vector3f(0, 0, 28));

  const PenetrationCounts counts = countPenetrations(frames);
  EXPECT_EQ(counts.frames, 4);         // every pose but the open one
  EXPECT_EQ(counts.in_solid, 2);       // blocks A and B
  EXPECT_EQ(counts.outside_world, 3);  // beyond the bounds, the void leaf, block B's
  EXPECT_EQ(countPenetrations({}).frames, 0);

  // Without the playable extent only the hull test remains.
  const quake3::CollisionModel brushes_only(model.brushes());
  const quake3::CameraKinematics bare(brushes_only, 50, 1024);
  EXPECT_FALSE(truthAt(bare, 600, 0).in_solid);
  EXPECT_FALSE(truthAt(bare, -300, 0).in_solid);
  EXPECT_TRUE(truthAt(bare, -400, 0).in_solid);
  EXPECT_FALSE(truthAt(bare, -400, 0).outside_world);
}

// A committed step whose frames penetrate for either reason is one event; its frames
// are the union, and each reason is counted apart: frames 1-3 of "uw" are in solid,
// 2-4 outside the world, so 4 penetrating frames from frame 1, 3 and 3 by reason.
TEST(EpisodeTruth, PenetrationEventsTellTheReasonsApart) {
  auto frame = [](bool hull, bool outside) {
    FrameTruth f;
    f.hull_in_solid = hull;
    f.outside_world = outside;
    f.in_solid = hull || outside;
    return f;
  };
  std::vector<StepRecord> history(1);
  history[0].step = 7;
  CandidateRecord c;
  c.verdict.candidate = "uw";
  c.truth = {frame(false, false), frame(true, false), frame(true, true), frame(true, true), frame(false, true),
             frame(false, false)};
  history[0].candidates = {c};
  history[0].chosen = 0;
  const std::vector<PenetrationEvent> events = penetrationEvents(history);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].frames, 4);
  EXPECT_EQ(events[0].frames_in_solid, 3);
  EXPECT_EQ(events[0].frames_outside_world, 3);
  EXPECT_EQ(events[0].first_frame, 1);
  EXPECT_EQ(committedInSolidFrames(history), 4);
}

// A nodraw player-clip brush stops the player but draws nothing: a hull in it alone is
// in solid, and its frame counts as clip-only; a hull that also touches a solid brush,
// one in a drawn clip brush (a grate), or one whose centre is outside the world, does
// not. The world: a floor (top z = 0), nodraw clip C at x in [100, 200] and solid D at
// x in [200, 300] side by side, drawn clip G at x in [-200, -100] (all |y| <= 50, 128
// high), bounds x, y in [-512, 512]. The hull spans |x| <= 15 around the camera:
//   (150, 0)   hull x in [135, 165], inside C only        -> in solid, clip only
//   (200, 0)   hull x in [185, 215], in C and D           -> in solid, not clip only
//   (250, 0)   hull x in [235, 265], inside D only        -> in solid, not clip only
//   (0, 0)     open floor                                 -> neither
//   (-150, 0)  inside G only                              -> in solid, not clip only
// Overlaps: C alone 0x10000 not drawn; C and D 0x10001 drawn (D); D 0x1 drawn; the floor
// under the hull is only touched: 0; G 0x10000 drawn.
TEST(EpisodeTruth, AHullInNodrawPlayerClipAloneIsAnInvisiblePenetration) {
  quake3::ConvexBrush clip = boxBrush({100, -50, 0}, {200, 50, 128});
  clip.contents = quake3::kContentsPlayerClip;
  clip.drawn = false;
  quake3::ConvexBrush grate = boxBrush({-200, -50, 0}, {-100, 50, 128});
  grate.contents = quake3::kContentsPlayerClip;
  quake3::PlayableWorld world;
  world.bounds = Eigen::AlignedBox3f(Eigen::Vector3f(-512, -512, -16), Eigen::Vector3f(512, 512, 256));
  const quake3::CollisionModel model(
      {boxBrush({-512, -512, -16}, {512, 512, 0}), clip, boxBrush({200, -50, 0}, {300, 50, 128}), grate}, world);
  const Eigen::Vector3f mins(-15, -15, -24), maxs(15, 15, 32);
  auto overlap = [&](float x) {
    const quake3::BoxOverlap o = model.boxOverlap({x, 0, 24}, mins, maxs);
    return std::make_pair(o.contents, o.drawn);
  };
  EXPECT_EQ(overlap(150), std::make_pair(quake3::kContentsPlayerClip, false));
  EXPECT_EQ(overlap(200), std::make_pair(quake3::kContentsPlayerClip | quake3::kContentsSolid, true));
  EXPECT_EQ(overlap(250), std::make_pair(quake3::kContentsSolid, true));
  EXPECT_EQ(overlap(0), std::make_pair(0, false));
  EXPECT_EQ(overlap(-150), std::make_pair(quake3::kContentsPlayerClip, true));

  const quake3::CameraKinematics k(model, 50, 1024);
  const std::vector<FrameTruth> frames = {truthAt(k, 150, 0), truthAt(k, 200, 0), truthAt(k, 250, 0),
                                          truthAt(k, 0, 0), truthAt(k, -150, 0)};
  const std::vector<std::array<bool, 2>> expected = {
      {true, true}, {true, false}, {true, false}, {false, false}, {true, false}};
  for (size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(frames[i].in_solid, expected[i][0]) << "pose " << i;
    EXPECT_EQ(frames[i].hull_in_clip_only, expected[i][1]) << "pose " << i;
  }
  const PenetrationCounts counts = countPenetrations(frames);
  EXPECT_EQ(counts.frames, 4);
  EXPECT_EQ(counts.in_solid, 4);
  EXPECT_EQ(counts.clip_only, 1);

  // Clip-only counts the frames whose one reason is the invisible clip: a hull in clip
  // whose centre is also outside the world counts as outside the world instead.
  FrameTruth outside = frames[0];
  outside.outside_world = true;
  EXPECT_EQ(countPenetrations({outside}).clip_only, 0);

  std::vector<StepRecord> history(1);
  history[0].step = 2;
  CandidateRecord c;
  c.verdict.candidate = "jw@15";
  c.truth = {frames[3], frames[0], frames[0], frames[1]};
  history[0].candidates = {c};
  history[0].chosen = 0;
  const std::vector<PenetrationEvent> events = penetrationEvents(history);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].frames, 3);
  EXPECT_EQ(events[0].frames_clip_only, 2);
  EXPECT_EQ(events[0].first_frame, 1);
}

// The floor in view of one committed frame, worked out by hand. A 4 x 4 image, fx = fy =
// cx = cy = 2; the camera stands 50 units over the floor (floor_z 0) at the origin and
// looks along +x (optical x = world -y, y = world -z, z = world +x). A pixel (u, v) has
// the ray ((u - 2) / 2, (v - 2) / 2, 1), and a depth d (m) puts its point at
// (0, 0, 50) + 32 d R ray. The reachable floor (1 m = 32 units cells): (3, 0) at z 0,
// (3, 1) at z 20 (a step up), (3, 3) at z -5, (6, 0) at z 0.
//   (2, 3), d 3.125: (100, 0, 0)    cell (3, 0), on its floor           -> in view, storey 0
//   (1, 3), d 3.125: (100, 50, 0)   cell (3, 1), 20 under its floor     -> no (over half a step)
//   (0, 3), d 3.125: (100, 100, 0)  cell (3, 3), 5 over its floor       -> in view, storey -1
//   (3, 3), d 3.125: (100, -50, 0)  cell (3, -2), not reachable         -> no
//   (2, 2), d 6.25:  (200, 0, 50)   cell (6, 0), but 50 over the frame's floor (a wall) -> no
//   (2, 1): NaN (sky); every other pixel 0 (no depth)
// At stride 2 only pixels (1, 1), (3, 1), (1, 3), (3, 3) are read: nothing in view.
TEST(EpisodeTruth, TheFloorInViewIsWhatTheTrueDepthSeesOnReachableFloor) {
  quake3::ReachableFloor reachable;
  reachable.cells = {{112, 16, 0}, {112, 48, 20}, {112, 112, -5}, {208, 16, 0}};
  const ReachableCells cells(reachable);
  CameraIntrinsics k;
  k.width = k.height = 4;
  k.fx = k.fy = k.cx = k.cy = 2;
  FrameTruth frame;
  Eigen::Matrix3d r;
  r << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  frame.camera_to_world.linear() = r;
  frame.camera_to_world.translation() = Eigen::Vector3d(0, 0, 50);
  frame.floor_z = 0;
  frame.depth_m = cv::Mat(4, 4, CV_32F, cv::Scalar(0));
  frame.depth_m.at<float>(3, 2) = 3.125f;
  frame.depth_m.at<float>(3, 1) = 3.125f;
  frame.depth_m.at<float>(3, 0) = 3.125f;
  frame.depth_m.at<float>(3, 3) = 3.125f;
  frame.depth_m.at<float>(2, 2) = 6.25f;
  frame.depth_m.at<float>(1, 2) = std::numeric_limits<float>::quiet_NaN();
  const double band = 9;  // eta_low 0.18 of a 50-unit eye
  const std::set<ReachableCells::CellStorey> expected = {{{3, 0}, 0}, {{3, 3}, -1}};
  EXPECT_EQ(cells.inViewOf(frame, k, band, 1), expected);
  EXPECT_TRUE(cells.inViewOf(frame, k, band, 2).empty());
  frame.depth_m = cv::Mat();
  EXPECT_TRUE(cells.inViewOf(frame, k, band, 1).empty());
}
