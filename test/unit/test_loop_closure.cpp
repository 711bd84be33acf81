// Loop closure (docs/loop_closure.md): the pose graph on synthetic loops with injected
// drift, the geometric verification on a synthetic textured wall (a true match is
// accepted with the right relative pose and scale, a wrong one rejected), and the
// committed keyframes' loop closure: a return to a mapped place pulls the drifted path
// back, and restoring a copy taken before the closure (what a rewind does) undoes it.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "valerant/common/error.h"
#include "valerant/config/config.h"
#include "valerant/explore/keyframe_features.h"
#include "valerant/explore/loop_closure.h"
#include "valerant/explore/loop_verifier.h"
#include "valerant/explore/pose_graph.h"
#include "valerant/map/corrected_keyframe.h"

using namespace valerant;

namespace {

Similarity3 at(double x, double y, double z, double yaw_deg = 0) {
  Similarity3 s;
  s.rotation = Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitY());
  s.translation = {x, y, z};
  return s;
}

// Chains relative measurements from node 0 (dead reckoning).
std::vector<Similarity3> deadReckoning(const Similarity3& start, const std::vector<Similarity3>& steps) {
  std::vector<Similarity3> out{start};
  for (const Similarity3& z : steps) out.push_back(out.back() * z);
  return out;
}

// A square path on the floor plane x-z: 4 sides of 4 unit steps, a 90 deg turn of yaw
// after each side; the true relative poses of the 16 steps.
std::vector<Similarity3> squareSteps() {
  std::vector<Similarity3> steps;
  for (int side = 0; side < 4; ++side)
    for (int i = 0; i < 4; ++i) steps.push_back(at(0, 0, 1, i == 3 ? 90 : 0));
  return steps;
}

}  // namespace

TEST(PoseGraph, AnOutAndBackCorridorSpreadsTheDriftEvenlyOverItsEdges) {
  // Hand-worked: 8 steps out along x, each measured 1.1 (truth 1), and 8 steps back,
  // each measured -1 (truth -1). Dead reckoning ends at x = 0.8; the loop edge says the
  // end is the start. All edges lie along x and weigh the same, so least squares spreads
  // the 0.8 evenly over the 17 edges: every odometry step shrinks by 0.8/17 and the end
  // lands at 0.8 - 16 * 0.8 / 17 = 0.8 / 17 = 0.0471 (a rotation would only move
  // residuals off their edges, so none is made).
  std::vector<Similarity3> steps;
  for (int i = 0; i < 8; ++i) steps.push_back(at(1.1, 0, 0));
  for (int i = 0; i < 8; ++i) steps.push_back(at(-1, 0, 0));
  const std::vector<Similarity3> initial = deadReckoning(Similarity3{}, steps);
  EXPECT_NEAR(initial.back().translation.x(), 0.8, 1e-12);
  std::vector<PoseGraphEdge> edges;
  for (size_t i = 0; i < steps.size(); ++i) edges.push_back({i, i + 1, steps[i]});
  edges.push_back({0, 16, Similarity3{}});
  const auto optimised = optimisePoseGraph(initial, edges, PoseGraphOptions{false, 1.0, 50, {}, 0}).nodes;
  // Ceres stops at its default function tolerance (1e-6 relative): 1e-4 here.
  EXPECT_NEAR(optimised.back().translation.x(), 0.8 / 17, 1e-4);
  EXPECT_NEAR(optimised[8].translation.x(), 8 * (1.1 - 0.8 / 17), 1e-4);  // the far end
  EXPECT_NEAR(optimised.back().translation.tail<2>().norm(), 0, 1e-6);
  EXPECT_NEAR(optimised.back().rotation.angularDistance(Eigen::Quaterniond::Identity()), 0, 1e-6);
  EXPECT_EQ(optimised.front().translation, Eigen::Vector3d::Zero());  // node 0 is the fixed gauge
}

TEST(PoseGraph, ASquareWithYawDriftIsPulledBackWithinATwentiethOfItsDrift) {
  // Each step's yaw is measured 1 deg too far: dead reckoning turns 16 deg too far in
  // all, and its end misses the start by 0.76 (computed below; the path is 16 long). The loop edge
  // (end = start) shares the inconsistency among 17 edges; linearised, the end keeps
  // about 1/17 of it: we ask for under 1/20 of the dead-reckoning miss in position and
  // under 1 deg in yaw. SE(3): the scale is not estimated.
  std::vector<Similarity3> measured = squareSteps();
  for (Similarity3& z : measured) z.rotation = z.rotation * Eigen::AngleAxisd(M_PI / 180, Eigen::Vector3d::UnitY());
  const std::vector<Similarity3> initial = deadReckoning(Similarity3{}, measured);
  const double miss = initial.back().translation.norm();
  EXPECT_NEAR(miss, 0.76, 0.01);
  EXPECT_NEAR(deadReckoning(Similarity3{}, squareSteps()).back().translation.norm(), 0, 1e-9);  // the truth closes
  std::vector<PoseGraphEdge> edges;
  for (size_t i = 0; i < measured.size(); ++i) edges.push_back({i, i + 1, measured[i]});
  edges.push_back({0, 16, Similarity3{}});
  const PoseGraphSolution solution = optimisePoseGraph(initial, edges, PoseGraphOptions{false, 1.0, 100, {}, 0});
  EXPECT_TRUE(solution.converged);
  // One iteration cannot meet Ceres' tolerances on this loop: the solution says so.
  EXPECT_FALSE(optimisePoseGraph(initial, edges, PoseGraphOptions{false, 1.0, 1, {}, 0}).converged);
  const std::vector<Similarity3>& optimised = solution.nodes;
  EXPECT_LT(optimised.back().translation.norm(), miss / 20);
  EXPECT_LT(optimised.back().rotation.angularDistance(Eigen::Quaterniond::Identity()) * 180 / M_PI, 1.0);
  for (const Similarity3& s : optimised) EXPECT_DOUBLE_EQ(s.scale, 1.0);
}

TEST(PoseGraph, Sim3AbsorbsAMonocularScaleDriftThatSE3CannotClose) {
  // A monocular SLAM's scale drifts: its units shrink, so step k of the square is
  // measured 1.03^k long (truth 1) while the SLAM believes its scale constant (odometry
  // edges carry scale 1). The loop edge, as a verified match measures it, carries the
  // scale between the end's units and the start's: 1.03^-16 = 0.623. Sim(3) gives each
  // keyframe its own scale: the end's comes out near 0.623 and the last step, mapped
  // through it, near its true length 1; SE(3) keeps every scale at 1, so the last step
  // stays 1.03^15 = 1.56 long in the map, and the end misses the start by more.
  const std::vector<Similarity3> truth = squareSteps();
  std::vector<Similarity3> measured = truth;
  for (size_t k = 0; k < measured.size(); ++k) measured[k].translation *= std::pow(1.03, k);
  const std::vector<Similarity3> initial = deadReckoning(Similarity3{}, measured);
  std::vector<PoseGraphEdge> edges;
  for (size_t i = 0; i < measured.size(); ++i) edges.push_back({i, i + 1, measured[i]});
  Similarity3 loop;
  loop.scale = std::pow(1.03, -16);
  edges.push_back({0, 16, loop});
  const auto sim3 = optimisePoseGraph(initial, edges, PoseGraphOptions{true, 1.0, 100, {}, 0}).nodes;
  const auto se3 = optimisePoseGraph(initial, edges, PoseGraphOptions{false, 1.0, 100, {}, 0}).nodes;
  const double miss = initial.back().translation.norm();
  const auto lastStep = [](const std::vector<Similarity3>& s) { return (s[16].translation - s[15].translation).norm(); };
  EXPECT_GT(miss, 1.0) << miss;
  EXPECT_NEAR(sim3.back().scale, std::pow(1.03, -16), 0.05) << sim3.back().scale;
  EXPECT_NEAR(lastStep(sim3), 1.0, 0.1) << lastStep(sim3);
  EXPECT_GT(lastStep(se3), 1.3) << lastStep(se3);
  EXPECT_LT(sim3.back().translation.norm(), 0.05 * miss) << sim3.back().translation.norm();
  EXPECT_LT(sim3.back().translation.norm(), se3.back().translation.norm()) << se3.back().translation.norm();
}

// Node 1 one unit from node 0 by an odometry edge of scale 1, its scale held to
// ln 0.8 (tau): the edge's ln-scale residual x and the prior's w (x - tau) give
// x = w^2 tau / (1 + w^2): s = 0.8^(1/2) at w = 1, 0.8^(4/5) at w = 2; the translation
// residual does not involve s_1, so node 1 stays at x = 1. A target far off (ln 0.2,
// past the Huber corner ln 1.5) pulls with a constant force: x + a = 0, s = 1 / 1.5.
TEST(PoseGraph, AScalePriorPullsTheScaleAgainstTheEdges) {
  const std::vector<Similarity3> initial = {Similarity3{}, at(1, 0, 0)};
  const std::vector<PoseGraphEdge> edges = {{0, 1, at(1, 0, 0)}};
  auto scaleWith = [&](double target, double weight) {
    PoseGraphOptions options{true, 1.0, 100, {}, 0};
    options.log_scale_targets = {std::nan(""), std::log(target)};
    options.scale_prior_weight = weight;
    const auto out = optimisePoseGraph(initial, edges, options).nodes;
    EXPECT_NEAR(out[1].translation.x(), 1, 1e-6);
    EXPECT_NEAR(out[0].scale, 1, 1e-12);  // the gauge
    return out[1].scale;
  };
  // Within Ceres' stopping tolerances (about 1e-5 here).
  EXPECT_NEAR(scaleWith(0.8, 1), std::sqrt(0.8), 1e-4);
  EXPECT_NEAR(scaleWith(0.8, 2), std::pow(0.8, 0.8), 1e-4);
  EXPECT_NEAR(scaleWith(0.2, 1), 1 / 1.5, 1e-3);
  EXPECT_NEAR(scaleWith(0.8, 0), 1, 1e-9);  // weight 0: no prior
  PoseGraphOptions wrong{true, 1.0, 100, {}, 0};
  wrong.log_scale_targets = {0.0};  // one target for two nodes
  wrong.scale_prior_weight = 1;
  EXPECT_THROW(optimisePoseGraph(initial, edges, wrong), InputError);
}

// Node 1 one unit from node 0 by an odometry edge of no turn; its floor, measured in its
// camera, stands theta off up (a tilt about x). Turning node 1 by phi about x costs phi^2
// on the edge (its rotation residual; the translation residual does not involve R_1) and
// w^2 |R_phi u - g|^2 = w^2 4 sin^2((theta - phi) / 2) on the prior: the minimum has
// phi = w^2 sin(theta - phi), phi = theta / 2 at w = 1 and 4 theta / 5 at w = 2 to first
// order (theta = 2 deg: within 1e-6 rad). Past the Huber corner a = w 2 sin(1.5 deg) the
// prior pulls with a constant force: phi = a w cos((theta - phi) / 2), 2.994 deg for
// theta = 10 deg at w = 1. Node 1 stays at x = 1.
TEST(PoseGraph, ALevelPriorTurnsTheFloorTowardUpAgainstTheEdges) {
  const std::vector<Similarity3> initial = {Similarity3{}, at(1, 0, 0)};
  const std::vector<PoseGraphEdge> edges = {{0, 1, at(1, 0, 0)}};
  const Eigen::Vector3d up(0, -1, 0);
  auto tiltWith = [&](double theta_deg, double weight) {
    PoseGraphOptions options{true, 1.0, 100, {}, 0};
    const Eigen::Vector3d tilted = Eigen::AngleAxisd(-theta_deg * M_PI / 180, Eigen::Vector3d::UnitX()) * up;
    options.floor_normals_in_camera = {Eigen::Vector3d::Zero(), tilted};
    options.up = up;
    options.level_prior_weight = weight;
    const auto out = optimisePoseGraph(initial, edges, options).nodes;
    EXPECT_NEAR(out[1].translation.x(), 1, 1e-6);
    EXPECT_NEAR(out[1].scale, 1, 1e-9);
    const Eigen::AngleAxisd turn(out[1].rotation);
    if (turn.angle() > 1e-9) EXPECT_NEAR(std::abs(turn.axis().x()), 1, 1e-6);  // about x alone
    return turn.angle() * (turn.axis().x() >= 0 ? 1 : -1) * 180 / M_PI;
  };
  // Within Ceres' stopping tolerances (about 1e-5 rad here, 1e-4 past the corner); without
  // the corner theta = 10 deg would give about 5 deg.
  EXPECT_NEAR(tiltWith(2, 1), 1.0, 1e-3);
  EXPECT_NEAR(tiltWith(2, 2), 1.6, 1e-3);
  EXPECT_NEAR(tiltWith(10, 1), 2.994, 1e-2);
  EXPECT_NEAR(tiltWith(2, 0), 0, 1e-9);  // weight 0: no prior
  PoseGraphOptions wrong{true, 1.0, 100, {}, 0};
  wrong.floor_normals_in_camera = {up};  // one normal for two nodes
  wrong.level_prior_weight = 1;
  EXPECT_THROW(optimisePoseGraph(initial, edges, wrong), InputError);
}

TEST(PoseGraph, AnEdgeToAMissingNodeIsAnError) {
  EXPECT_THROW(optimisePoseGraph({Similarity3{}, Similarity3{}}, {{0, 2, Similarity3{}}}, PoseGraphOptions{}), InputError);
  EXPECT_THROW(optimisePoseGraph({}, {}, PoseGraphOptions{}), InputError);
}

// Scale 2 about the origin moves the unit cube's corner (1, 1, 1) by sqrt 3, the farthest;
// a shift moves every point by its length; a quarter turn about +y takes the segment's end
// (2, 0, 0) to (0, 0, -2), 2 sqrt 2 away (its other end (1, 0, 0) moves sqrt 2).
TEST(Similarity3, TheFarthestMoveOverABoxIsAtACorner) {
  const Eigen::AlignedBox3d cube(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1));
  Similarity3 doubling;
  doubling.scale = 2;
  EXPECT_NEAR(doubling.maxDisplacement(cube), std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(at(0.3, 0, 0.4).maxDisplacement(cube), 0.5, 1e-12);
  const Eigen::AlignedBox3d segment(Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(2, 0, 0));
  EXPECT_NEAR(at(0, 0, 0, 90).maxDisplacement(segment), 2 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(Similarity3{}.maxDisplacement(cube), 0, 0);
}

TEST(Similarity3, ComposesInvertsAndMovesCameras) {
  Similarity3 s = at(1, 2, 3, 90);
  s.scale = 2;
  const Eigen::Vector3d p(1, 0, 0);
  // Yaw 90 deg about +y takes x to -z: 2 * (0, 0, -1) + (1, 2, 3).
  EXPECT_TRUE(s.apply(p).isApprox(Eigen::Vector3d(1, 2, 1), 1e-12));
  EXPECT_TRUE((s.inverse() * s).translation.isZero(1e-12));
  EXPECT_NEAR((s * s.inverse()).scale, 1, 1e-12);
  Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();
  camera.translation() = p;
  EXPECT_TRUE(s.applyTo(camera).translation().isApprox(Eigen::Vector3d(1, 2, 1), 1e-12));
  EXPECT_NEAR(Eigen::Quaterniond(s.applyTo(camera).linear()).angularDistance(s.rotation), 0, 1e-12);
}

namespace {

// A textured wall z = kWallZ (camera frame of a camera at x, looking along +z), seen at
// 320x240 with a 90 deg field of view: fx = 160, so the view shifts 40 px per unit of x.
constexpr double kWallZ = 4;
const CameraIntrinsics kCamera = CameraIntrinsics::fromHorizontalFov(320, 240, 90);

// The episode's anchor floor in these scenes: one unit under a camera at the origin
// (kappa_0 = 1), y down (the camera's), so up is -y.
FloorPlane anchorFloor() {
  FloorPlane floor;
  floor.c = Eigen::Vector3d::Zero();
  floor.q = {0, 1, 0};
  floor.n = {0, -1, 0};
  return floor;
}
const FloorPlane kAnchor = anchorFloor();

cv::Mat wallTexture(uint64_t seed) {
  cv::Mat texture(240, 1600, CV_8UC3, cv::Scalar(90, 90, 90));
  cv::RNG rng(seed);
  for (int i = 0; i < 1500; ++i) {
    const cv::Point a(rng.uniform(0, texture.cols), rng.uniform(0, texture.rows));
    const cv::Point b = a + cv::Point(rng.uniform(4, 30), rng.uniform(4, 30));
    cv::rectangle(texture, a, b, cv::Scalar(rng.uniform(0, 255), rng.uniform(0, 255), rng.uniform(0, 255)), cv::FILLED);
  }
  return texture;
}

// The view of a camera at x (a multiple of 0.025: whole pixels) in [0, 25].
cv::Mat wallView(const cv::Mat& texture, double x) {
  const int shift = static_cast<int>(std::lround(x * kCamera.fx / kWallZ));
  return texture(cv::Rect(shift, 0, 320, 240)).clone();
}

// The wall as the camera's keyframe cloud (every 2nd pixel), in a SLAM frame where the
// camera is at `slam_pose`; `units`: SLAM units per true unit (a monocular scale).
KeyframeCloud wallCloud(const Eigen::Isometry3d& slam_pose, double units, int index) {
  KeyframeCloud cloud;
  cloud.keyframe = index;
  cloud.frame = index;
  cloud.camera_to_map = slam_pose;
  for (int v = 0; v < kCamera.height; v += 2)
    for (int u = 0; u < kCamera.width; u += 2) {
      const Eigen::Vector3d c(kWallZ * (u - kCamera.cx) / kCamera.fx, kWallZ * (v - kCamera.cy) / kCamera.fy, kWallZ);
      CloudPoint p;
      p.position = (slam_pose * (units * c)).cast<float>();
      p.confidence = 10;
      cloud.points.push_back(p);
    }
  return cloud;
}

Eigen::Isometry3d atX(double x) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation().x() = x;
  return pose;
}

}  // namespace

TEST(LoopVerifier, ATrueMatchGivesTheRelativePoseAndScale) {
  // The old keyframe at x = 1 (SLAM units = true units), the new one at x = 1.5 with a
  // SLAM scale twice the old one's: its own cloud says the wall is 8 away. Expected:
  // the new camera 0.5 to the right in the old camera's frame, scale 1/2 (new units to
  // old), no rotation.
  const LoopClosureConfig config;
  const cv::Mat texture = wallTexture(1);
  const KeyframeFeatures old_kf = describeKeyframe(wallView(texture, 1), wallCloud(atX(1), 1, 0), kCamera, config);
  const KeyframeFeatures new_kf = describeKeyframe(wallView(texture, 1.5), wallCloud(atX(3), 2, 1), kCamera, config);
  EXPECT_GT(old_kf.withDepth(), 200u);
  Similarity3 predicted = at(0.6, 0, 0);
  predicted.scale = 0.55;
  const LoopVerification v = verifyLoop(old_kf, new_kf, predicted, 1.0, true, kCamera, config);
  ASSERT_TRUE(v.accepted) << v.detail;
  EXPECT_GE(v.inliers, config.min_inliers);
  EXPECT_TRUE(v.relative.translation.isApprox(Eigen::Vector3d(0.5, 0, 0), 0.02)) << v.relative.translation.transpose();
  EXPECT_NEAR(v.relative.scale, 0.5, 0.01);
  EXPECT_LT(v.rotation_deg, 0.5);
  EXPECT_NEAR(v.offset_eye_heights, 0.1, 0.02);
}

TEST(LoopVerifier, RejectsAnotherPlaceAndAMatchFarFromThePrediction) {
  const LoopClosureConfig config;
  const cv::Mat texture = wallTexture(1);
  const KeyframeFeatures old_kf = describeKeyframe(wallView(texture, 1), wallCloud(atX(1), 1, 0), kCamera, config);
  // Another wall altogether: nothing matches.
  const KeyframeFeatures elsewhere =
      describeKeyframe(wallView(wallTexture(2), 1), wallCloud(atX(1), 1, 1), kCamera, config);
  const LoopVerification other = verifyLoop(old_kf, elsewhere, Similarity3{}, 1.0, true, kCamera, config);
  EXPECT_FALSE(other.accepted);
  // Rectangle corners look alike: a few chance matches may pass the ratio test, but
  // they do not agree on one pose.
  EXPECT_TRUE(other.reason == "few_matches" || other.reason == "few_inliers") << other.detail;
  // The same-looking wall, but the pose graph puts the new keyframe 5 eye heights away:
  // a wrong match (a repeated texture elsewhere) that would tear the map.
  const KeyframeFeatures same = describeKeyframe(wallView(texture, 1), wallCloud(atX(1), 1, 1), kCamera, config);
  const LoopVerification far = verifyLoop(old_kf, same, at(5, 0, 0), 1.0, true, kCamera, config);
  EXPECT_FALSE(far.accepted);
  EXPECT_EQ(far.reason, "offset") << far.detail;
  EXPECT_NEAR(far.offset_eye_heights, 5, 0.1);
  // Turned 30 deg away in the prediction: above max_rotation_deg (20).
  const LoopVerification turned = verifyLoop(old_kf, same, at(0, 0, 0, 30), 1.0, true, kCamera, config);
  EXPECT_EQ(turned.reason, "rotation") << turned.detail;
}

namespace {

// One committed "step" of the corridor: the camera walks along the wall from true x
// `from` to `to` in steps of 0.25 (one keyframe per frame); the SLAM's x drifts by
// `drift` per frame since the start.
struct Corridor {
  cv::Mat texture = wallTexture(3);
  double drift = 0.02;
  size_t frames = 0;  // frames committed so far

  BranchResult walk(double from, double to) {
    BranchResult r;
    const int n = static_cast<int>(std::lround(std::abs(to - from) / 0.25));
    for (int i = 1; i <= n; ++i) {
      const double x = from + (to > from ? 0.25 : -0.25) * i;
      const Eigen::Isometry3d slam_pose = atX(x + drift * static_cast<double>(frames));
      r.rollout.frames.push_back(wallView(texture, x));
      r.poses.push_back(slam_pose);
      r.keyframes.push_back(wallCloud(slam_pose, 1, static_cast<int>(frames)));
      FloorPlane floor;
      floor.c = slam_pose.translation();
      floor.q = floor.c + Eigen::Vector3d(0, 1, 0);
      floor.n = {0, -1, 0};
      r.keyframe_floors.push_back(floor);
      ++frames;
    }
    return r;
  }
};

void fuse(const BranchResult& r, MapFusion& map, std::vector<Eigen::Isometry3d>& trajectory) {
  for (size_t i = 0; i < r.keyframes.size(); ++i) map.fuse(r.keyframes[i], r.keyframe_floors[i]);
  trajectory.insert(trajectory.end(), r.poses.begin(), r.poses.end());
}

}  // namespace

TEST(LoopClosure, AReturnToAMappedPlaceCorrectsThePathAndARewindUndoesIt) {
  // Out along the wall from x = 0 to 3 (12 frames), then back to 0 (12 frames), the
  // SLAM drifting 0.02 a frame: back at x = 0.25 after 23 frames it believes x = 0.71.
  // min_age_keyframes 6 and radius 1: the way back matches the way out, the way out
  // nothing (6 frames back is 1.5 away). After the closures the end
  // must be within 0.1 of the truth (under a quarter of the drift; the graph shares the
  // odometry's disagreement with the loop edges), earlier frames moved too,
  // and the map's keyframes replaced; a copy taken before the way back restores the
  // uncorrected map (same keyframe ids) and trajectory.
  Config config;
  config.loop_closure.enabled = true;
  config.loop_closure.min_age_keyframes = 6;
  config.loop_closure.radius_eye_heights = 1;  // the way out never reaches 6 frames back
  LoopClosure closure(config.loop_closure, kCamera, true);
  MapFusion map(config.map, config.collision);
  std::vector<Eigen::Isometry3d> trajectory;
  Corridor corridor;
  BranchResult start = corridor.walk(-0.25, 0);  // the context: one frame at x = 0
  fuse(start, map, trajectory);
  EXPECT_FALSE(closure.commit(start, 0, kAnchor, map, trajectory));
  const BranchResult out = corridor.walk(0, 3);
  fuse(out, map, trajectory);
  EXPECT_FALSE(closure.commit(out, 1, kAnchor, map, trajectory));  // nothing old enough nearby
  EXPECT_EQ(closure.made(), 0u);

  const LoopClosure before = closure;  // what a checkpoint keeps
  const std::vector<Eigen::Isometry3d> trajectory_before = trajectory;
  std::vector<uint64_t> ids_before;
  for (const auto& kf : map.keyframes()) ids_before.push_back(kf->id);

  const BranchResult back = corridor.walk(3, 0.25);
  fuse(back, map, trajectory);
  const double drifted = trajectory.back().translation().x() - 0.25;
  EXPECT_NEAR(drifted, 0.02 * 23, 1e-9);
  EXPECT_TRUE(closure.commit(back, 2, kAnchor, map, trajectory));
  EXPECT_GT(closure.made(), 0u);
  EXPECT_LT(std::abs(trajectory.back().translation().x() - 0.25), 0.1);
  EXPECT_EQ(trajectory.size(), corridor.frames);
  EXPECT_EQ(map.marker(), corridor.frames);
  EXPECT_NE(map.keyframes()[6]->id, ids_before[6]);  // a keyframe of the way out, replaced
  // The map follows: the last keyframe's wall points sit where the truth puts them.
  EXPECT_NEAR(map.keyframes().back()->camera_to_map.translation().x(), trajectory.back().translation().x(), 1e-9);

  closure = before;  // the rewind
  closure.restoreInto(map, trajectory);
  ASSERT_EQ(trajectory.size(), trajectory_before.size());
  for (size_t i = 0; i < trajectory.size(); ++i) EXPECT_TRUE(trajectory[i].isApprox(trajectory_before[i]));
  ASSERT_EQ(map.marker(), ids_before.size());
  for (size_t i = 0; i < ids_before.size(); ++i) EXPECT_EQ(map.keyframes()[i]->id, ids_before[i]);
  EXPECT_EQ(closure.made(), 0u);
}

namespace {
// One keyframe per frame along the wall at true x = 0.25 i, each with its floor
// `kappa` SLAM units under the camera; no images (no loop candidates).
BranchResult keyframesAt(const std::vector<double>& xs, double kappa, size_t first_frame) {
  BranchResult r;
  for (size_t i = 0; i < xs.size(); ++i) {
    const Eigen::Isometry3d pose = atX(xs[i]);
    r.poses.push_back(pose);
    r.keyframes.push_back(wallCloud(pose, 1, static_cast<int>(first_frame + i)));
    FloorPlane floor;
    floor.c = pose.translation();
    floor.q = floor.c + Eigen::Vector3d(0, kappa, 0);
    floor.n = {0, -1, 0};
    r.keyframe_floors.push_back(floor);
  }
  return r;
}

// Loop closure with the eye height alone (no loop candidates), at factor weight `weight`.
Config eyeHeightAlone(double weight) {
  Config config;
  config.loop_closure.enabled = true;
  config.loop_closure.max_candidates = 0;
  config.loop_closure.eye_height_weight = weight;
  return config;
}

void fuseAndCommit(const BranchResult& r, int step, LoopClosure& closure, MapFusion& map,
                   std::vector<Eigen::Isometry3d>& trajectory, bool moves) {
  fuse(r, map, trajectory);
  EXPECT_EQ(closure.commit(r, step, kAnchor, map, trajectory), moves) << "step " << step;
}

// The start (1 over its floor, kappa_0 = 1) and commit A (a keyframe at x = 0.25, 0.8 over
// its own): a scale correction, as in AKeyframeWhoseEyeStandsLowRescalesTheMap.
void commitStartAndA(LoopClosure& closure, MapFusion& map, std::vector<Eigen::Isometry3d>& trajectory) {
  fuseAndCommit(keyframesAt({0}, 1.0, 0), 0, closure, map, trajectory, false);
  fuseAndCommit(keyframesAt({0.25}, 0.8, 1), 1, closure, map, trajectory, true);
}
}  // namespace

// The start's keyframe stands 1 over its floor (kappa_0 = 1); the next commit's one keyframe
// 0.8 over its own: the SLAM's scale shrank by 0.8, 0.22 in ln against the tolerance's
// ln 1.1 = 0.095, so the commit corrects the scale alone (no loop candidate, max_candidates
// 0). By PoseGraph.AScalePriorPullsTheScaleAgainstTheEdges at w = 1 its node takes scale
// (1 / 0.8)^(1/2) = 1.118, and the map's keyframe with it. Off (weight 0), within the
// tolerance (0.95 over its floor), or when the commit is a turn in place (no baseline: its
// floor measures no scale), nothing moves.
TEST(LoopClosure, AKeyframeWhoseEyeStandsLowRescalesTheMap) {
  auto run = [](double weight, double kappa, bool turn = false) {
    const Config config = eyeHeightAlone(weight);
    LoopClosure closure(config.loop_closure, kCamera, true);
    MapFusion map(config.map, config.collision);
    std::vector<Eigen::Isometry3d> trajectory;
    const BranchResult start = keyframesAt({0}, 1.0, 0);
    fuse(start, map, trajectory);
    EXPECT_FALSE(closure.commit(start, 0, kAnchor, map, trajectory));
    BranchResult next = keyframesAt({0.25}, kappa, 1);
    next.verdict.rotation_only = turn;
    fuse(next, map, trajectory);
    const bool moved = closure.commit(next, 1, kAnchor, map, trajectory);
    EXPECT_EQ(closure.scaleCorrections(), moved ? 1u : 0u);
    EXPECT_EQ(closure.made(), 0u);
    return std::pair{moved, closure.correction(1).scale};
  };
  const auto [moved, scale] = run(1, 0.8);
  EXPECT_TRUE(moved);
  EXPECT_NEAR(scale, std::sqrt(1 / 0.8), 1e-4);
  EXPECT_EQ(run(0, 0.8), std::pair(false, 1.0));
  EXPECT_EQ(run(1, 0.95), std::pair(false, 1.0));
  EXPECT_EQ(run(1, 0.8, true), std::pair(false, 1.0));
}

// The start stands level over its floor (kappa_0 = 1, up -y); the next commit's one
// keyframe at x = 0.25 has a floor fitted on it whose normal stands 2 deg off up (a tilt
// about x), its eye still 1 over it. With the level factor alone (weight 1, tolerance
// 1 deg) the commit corrects the tilt: by PoseGraph.ALevelPriorTurnsTheFloorTowardUpAgainstTheEdges
// its node turns by 1 deg toward level, and the map's keyframe with it (its camera stays
// where it was: the turn is about the node's camera). Off (weight 0), within the tolerance
// (2.5 deg), or on a floor not fitted on the keyframe (propagated), nothing moves.
TEST(LoopClosure, AKeyframeWhoseFloorStandsTiltedLevelsTheMap) {
  auto run = [](double weight, double tolerance_deg, bool fitted, double heading_deg = 0, bool in_place = false) {
    Config config;
    config.loop_closure.enabled = true;
    config.loop_closure.max_candidates = 0;
    config.loop_closure.level_weight = weight;
    config.loop_closure.level_tolerance_deg = tolerance_deg;
    LoopClosure closure(config.loop_closure, kCamera, true);
    MapFusion map(config.map, config.collision);
    std::vector<Eigen::Isometry3d> trajectory;
    fuseAndCommit(keyframesAt({0}, 1.0, 0), 0, closure, map, trajectory, false);
    BranchResult next = keyframesAt({0.25}, 1.0, 1);
    FloorPlane& floor = next.keyframe_floors[0];
    floor.n = Eigen::AngleAxisd(-2 * M_PI / 180, Eigen::Vector3d::UnitX()) * kAnchor.n;
    floor.q = floor.c - floor.n;
    floor.reliable = fitted;
    next.verdict.rotation_only = in_place;
    // The camera's heading (a turn about up) changes its floor normal's camera coordinates,
    // not the correction: the odometry edge penalises the correction's angle alone.
    const Eigen::Matrix3d heading = Eigen::AngleAxisd(heading_deg * M_PI / 180, kAnchor.n).toRotationMatrix();
    next.poses[0].linear() = heading;
    next.keyframes[0].camera_to_map.linear() = heading;
    fuse(next, map, trajectory);
    const bool moved = closure.commit(next, 1, kAnchor, map, trajectory);
    EXPECT_EQ(closure.levelCorrections(), moved ? 1u : 0u);
    EXPECT_EQ(closure.scaleCorrections(), 0u);
    EXPECT_EQ(closure.corrections(), moved ? 1u : 0u);
    const Eigen::AngleAxisd turn(closure.correction(1).rotation);
    if (moved) {
      EXPECT_NEAR(turn.angle() * 180 / M_PI, 1.0, 1e-3);
      EXPECT_NEAR(std::abs(turn.axis().x()), 1, 1e-6);
      EXPECT_NEAR((map.keyframes()[1]->camera_to_map.translation() - Eigen::Vector3d(0.25, 0, 0)).norm(), 0, 1e-6);
      const Eigen::Vector3d corrected = closure.correction(1).rotation * floor.n;
      EXPECT_NEAR(std::acos(corrected.dot(kAnchor.n)) * 180 / M_PI, 1.0, 1e-3);  // half the tilt left
    }
    return std::pair{moved, turn.angle()};
  };
  EXPECT_TRUE(run(1, 1.0, true).first);
  EXPECT_TRUE(run(1, 1.0, true, 90).first);
  EXPECT_EQ(run(0, 1.0, true), std::pair(false, 0.0));
  EXPECT_EQ(run(1, 2.5, true), std::pair(false, 0.0));
  EXPECT_EQ(run(1, 1.0, false), std::pair(false, 0.0));
  EXPECT_EQ(run(1, 1.0, true, 0, true), std::pair(false, 0.0));  // a turn in place measures no level
}

// [ours] dead_pocket.keep_map. The start stands 1 over its floor; commit A's keyframe at
// x = 0.25 0.8 over its own (a scale correction, as above); a checkpoint; commit B's
// keyframe at x = 0.5 stands 0.6 over its floor, which A's scale 1.118 takes to 0.67:
// a second correction, which rescales A's keyframe too (its points about its camera).
// The rewind to the checkpoint undoes it (A's keyframe as the checkpoint had it) and
// keeps B's keyframe as a passenger of the anchor, A's node: its camera and points where
// A's correction at the checkpoint puts them.
// The map holds the three, and a later commit fuses after them.
TEST(LoopClosure, ARewindThatKeepsTheMapKeepsTheDiscardedKeyframesOnTheAnchor) {
  const Config config = eyeHeightAlone(1);
  LoopClosure closure(config.loop_closure, kCamera, true);
  MapFusion map(config.map, config.collision);
  std::vector<Eigen::Isometry3d> trajectory;
  commitStartAndA(closure, map, trajectory);
  const LoopClosure checkpoint = closure;
  const Eigen::Vector3f a_point = map.keyframes()[1]->points.at(0).position;
  const Similarity3 anchor = checkpoint.correction(1);
  EXPECT_NEAR(anchor.scale, std::sqrt(1 / 0.8), 1e-4);

  const BranchResult b = keyframesAt({0.5}, 0.6, 2);
  fuse(b, map, trajectory);
  const std::shared_ptr<const FusedKeyframe> b_slam = map.keyframes()[2];  // as the SLAM made it
  EXPECT_TRUE(closure.commit(b, 2, kAnchor, map, trajectory));
  EXPECT_EQ(closure.corrections(), 2u);
  EXPECT_GT((map.keyframes()[1]->points.at(0).position - a_point).norm(), 1e-3);

  LoopClosure restored = checkpoint;
  restored.keepKeyframesOf(closure);
  restored.restoreInto(map, trajectory);
  EXPECT_EQ(restored.corrections(), 1u);
  EXPECT_EQ(restored.keyframes(), 2u);  // B's keyframe is no node
  ASSERT_EQ(map.marker(), 3u);
  ASSERT_EQ(trajectory.size(), 2u);
  EXPECT_LT((map.keyframes()[1]->points.at(0).position - a_point).norm(), 1e-6);
  EXPECT_LT((map.keyframes()[2]->camera_to_map.translation() - anchor.applyTo(atX(0.5)).translation()).norm(), 1e-9);
  EXPECT_LT((map.keyframes()[2]->points.at(0).position.cast<double>() -
             anchor.apply(b_slam->points.at(0).position.cast<double>())).norm(), 1e-5);

  const BranchResult c = keyframesAt({0.25}, 0.8 * 0.8, 3);  // from A again, the scale as at A
  fuse(c, map, trajectory);
  restored.commit(c, 2, kAnchor, map, trajectory);
  EXPECT_EQ(map.marker(), 4u);
  EXPECT_EQ(trajectory.size(), 3u);
  // A state the checkpoint did not lead to cannot lend it keyframes.
  EXPECT_THROW(LoopClosure(checkpoint).keepKeyframesOf(LoopClosure(config.loop_closure, kCamera, true)), InputError);
}

// [ours] loop_closure.rewrite_tolerance_eye_heights. As above: A's correction (scale
// 1.118) copies A's keyframe; B's second correction moves A's node again, which would
// move A's copy by at most d over the box of its points and camera (Similarity3's
// maxDisplacement, checked by hand above). A tolerance just over d keeps A's copy (same
// id, every point within the tolerance of where the exact correction puts it) and copies
// only B's; just under d copies A's again. The count of copies says which happened.
TEST(LoopClosure, ACorrectionThatMovesAKeyframeWithinTheToleranceKeepsItsCopy) {
  struct Played {
    std::shared_ptr<const FusedKeyframe> a_after_a, a_after_b;  // A's map keyframe
    Similarity3 a_correction_after_a, a_correction_after_b;
    size_t rewritten = 0;
  };
  const auto play = [](double tolerance) {
    Config config = eyeHeightAlone(1);
    config.loop_closure.rewrite_tolerance_eye_heights = tolerance;
    LoopClosure closure(config.loop_closure, kCamera, true);
    MapFusion map(config.map, config.collision);
    std::vector<Eigen::Isometry3d> trajectory;
    Played out;
    commitStartAndA(closure, map, trajectory);
    EXPECT_EQ(closure.keyframesRewritten(), 1u);  // A's; the start's node is the gauge
    out.a_after_a = map.keyframes()[1];
    out.a_correction_after_a = closure.correction(1);
    fuseAndCommit(keyframesAt({0.5}, 0.6, 2), 2, closure, map, trajectory, true);
    out.a_after_b = map.keyframes()[1];
    out.a_correction_after_b = closure.correction(1);
    out.rewritten = closure.keyframesRewritten();
    return out;
  };
  const Played exact = play(0);
  EXPECT_NE(exact.a_after_b, exact.a_after_a);
  EXPECT_EQ(exact.rewritten, 3u);
  Eigen::AlignedBox3d box(exact.a_after_a->camera_to_map.translation());
  for (const FusedPoint& p : exact.a_after_a->points) box.extend(p.position.cast<double>());
  const double d = (exact.a_correction_after_b * exact.a_correction_after_a.inverse()).maxDisplacement(box);
  EXPECT_GT(d, 1e-3);

  const Played tolerant = play(1.01 * d);
  EXPECT_EQ(tolerant.a_after_b, tolerant.a_after_a);  // A's copy kept
  EXPECT_EQ(tolerant.rewritten, 2u);                  // A's, then B's
  double worst = 0;  // kept, A's points stand within the tolerance of the exact correction
  for (size_t i = 0; i < exact.a_after_b->points.size(); ++i)
    worst = std::max(worst, double((tolerant.a_after_b->points[i].position - exact.a_after_b->points[i].position).norm()));
  EXPECT_GT(worst, 1e-4);  // the copy kept is not the exact one ...
  EXPECT_LE(worst, 1.01 * d + 1e-5);  // ... but as near as the tolerance

  const Played strict = play(0.99 * d);
  EXPECT_NE(strict.a_after_b, strict.a_after_a);
  EXPECT_EQ(strict.rewritten, 3u);
}

TEST(LoopClosure, ACommitThatDoesNotEndTheTrajectoryIsAnError) {
  LoopClosure closure(LoopClosureConfig{}, kCamera, true);
  Config config;
  MapFusion map(config.map, config.collision);
  std::vector<Eigen::Isometry3d> trajectory;
  Corridor corridor;
  const BranchResult r = corridor.walk(0, 1);
  EXPECT_THROW(closure.commit(r, 1, kAnchor, map, trajectory), InputError);
}

TEST(CorrectedKeyframe, MovesPointsAndCameraUnderANewId) {
  FusedKeyframe kf;
  kf.id = 7;
  kf.camera_to_map = Eigen::Isometry3d::Identity();
  FusedPoint p;
  p.position = {1, 0, 0};
  p.h = 0.5f;
  kf.points.push_back(p);
  Similarity3 c = at(0, 0, 2);
  c.scale = 3;
  const auto moved = correctedKeyframe(kf, c);
  EXPECT_NE(moved->id, 7u);
  EXPECT_TRUE(moved->points[0].position.isApprox(Eigen::Vector3f(3, 0, 2)));
  EXPECT_FLOAT_EQ(moved->points[0].h, 0.5f);  // floor-normalised: unchanged
  EXPECT_TRUE(moved->camera_to_map.translation().isApprox(Eigen::Vector3d(0, 0, 2)));
}

TEST(LoopClosureConfig, ShippedOffWithTheBuiltInValuesAndCheckedLikeTheRest) {
  const std::string shipped = std::string(VALERANT_SOURCE_DIR) + "/config/valerant.yaml";
  const LoopClosureConfig c = loadConfig(shipped).loop_closure;
  const LoopClosureConfig built_in;
  EXPECT_FALSE(c.enabled);  // off: the map is the SLAM's, as before
  EXPECT_EQ(c.min_age_keyframes, built_in.min_age_keyframes);
  EXPECT_EQ(c.radius_eye_heights, built_in.radius_eye_heights);
  EXPECT_EQ(c.max_view_angle_deg, built_in.max_view_angle_deg);
  EXPECT_EQ(c.max_candidates, built_in.max_candidates);
  EXPECT_EQ(c.features, built_in.features);
  EXPECT_EQ(c.ratio, built_in.ratio);
  EXPECT_EQ(c.max_distance, built_in.max_distance);
  EXPECT_EQ(c.min_matches, built_in.min_matches);
  EXPECT_EQ(c.min_inliers, built_in.min_inliers);
  EXPECT_EQ(c.pnp_threshold_px, built_in.pnp_threshold_px);
  EXPECT_EQ(c.max_offset_eye_heights, built_in.max_offset_eye_heights);
  EXPECT_EQ(c.max_rotation_deg, built_in.max_rotation_deg);
  EXPECT_EQ(c.max_scale_ratio, built_in.max_scale_ratio);
  EXPECT_EQ(c.max_iterations, built_in.max_iterations);
  EXPECT_EQ(c.eye_height_weight, built_in.eye_height_weight);  // 0: off
  EXPECT_EQ(c.eye_height_tolerance, built_in.eye_height_tolerance);
  EXPECT_EQ(c.rewrite_tolerance_eye_heights, built_in.rewrite_tolerance_eye_heights);
  EXPECT_EQ(c.level_weight, built_in.level_weight);  // 0: off
  EXPECT_EQ(c.level_tolerance_deg, built_in.level_tolerance_deg);
  const auto errorOf = [&](const std::string& assignment) {
    ConfigDocument d = ConfigDocument::load(shipped);
    d.setAssignment(assignment, "--set " + assignment);
    try {
      d.parse();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(errorOf("loop_closure.max_scale_ratio=0.5"),
            "--set loop_closure.max_scale_ratio=0.5: loop_closure.max_scale_ratio: value 0.5 outside [1, 100]");
  EXPECT_EQ(errorOf("loop_closure.enabled=maybe"),
            "--set loop_closure.enabled=maybe: loop_closure.enabled: expected true or false, got 'maybe'");
  EXPECT_NE(errorOf("loop_closure.min_inliers=100").find("loop_closure.min_inliers: must not exceed"), std::string::npos);
  EXPECT_EQ(errorOf("loop_closure.eye_height_weight=-1"),
            "--set loop_closure.eye_height_weight=-1: loop_closure.eye_height_weight: value -1 outside [0, 1e+06]");
  EXPECT_EQ(errorOf("loop_closure.rewrite_tolerance_eye_heights=2"),
            "--set loop_closure.rewrite_tolerance_eye_heights=2: loop_closure.rewrite_tolerance_eye_heights: value 2 "
            "outside [0, 1]");
  EXPECT_EQ(errorOf("loop_closure.level_tolerance_deg=91"),
            "--set loop_closure.level_tolerance_deg=91: loop_closure.level_tolerance_deg: value 91 outside [0, 90]");
  EXPECT_EQ(errorOf("loop_closure.enabled=true"), "");
}
