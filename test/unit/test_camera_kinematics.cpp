// The engine world's camera: exact yaw and displacement per candidate, floor
// following on stairs, a ramp and a drop, and walking through walls like a video
// world model (never stopped, flagged in solid).
#include <gtest/gtest.h>

#include <cmath>

#include "brush_world.h"
#include "valerant/world/quake3/camera_kinematics.h"

using namespace valerant;
using namespace valerant::quake3;
using valerant::test::boxBrush;

namespace {

// A corridor along +X: floor top z = 0 for x in [-512, 1024]; a 16-unit stair from
// x = 200; a wall across x in [600, 632]; a 64-unit block at x in [-400, -300] (too
// high to step on); a pit floor at z = -128 beyond x = -512; a ramp at y in [300, 500]
// rising 0.5 per unit from x = 100 to x = 228.
CollisionModel corridor() {
  std::vector<ConvexBrush> brushes = {
      boxBrush({-512, -256, -16}, {1024, 256, 0}),    // floor
      boxBrush({200, -256, 0}, {1024, 256, 16}),      // stair
      boxBrush({600, -256, 16}, {632, 256, 300}),     // wall on the stair
      boxBrush({-400, -256, 0}, {-300, 256, 64}),     // block
      boxBrush({-1024, -256, -144}, {-512, 256, -128}),  // pit floor
      boxBrush({-512, 256, -16}, {1024, 600, 0}),     // floor under the ramp
  };
  ConvexBrush ramp;
  const Eigen::Vector3f n = Eigen::Vector3f(-0.5f, 0, 1).normalized();
  ramp.planes = {{n.x(), n.y(), n.z(), -50.f * n.z()},  // z <= 0.5 (x - 100)
                 {1, 0, 0, 228}, {0, 1, 0, 500}, {0, -1, 0, -300}, {0, 0, -1, 0}};
  ramp.bounds = Eigen::AlignedBox3f(Eigen::Vector3f(100, 300, 0), Eigen::Vector3f(228, 500, 64));
  ramp.contents = kContentsSolid;
  brushes.push_back(ramp);
  return CollisionModel(brushes);
}

SpawnPoint spawnAt(float x, float y, float yaw) {
  SpawnPoint s;
  s.origin = {x, y, 24.f + 9.f};  // spawn origins float a little above the floor
  s.yaw_deg = yaw;
  return s;
}

CameraState run(const CameraKinematics& k, CameraState s, const ActionSequence& seq,
                int* in_solid_frames = nullptr) {
  for (const auto& step : seq.steps) {
    s = k.step(s, step);
    if (in_solid_frames) *in_solid_frames += k.inSolid(s);
  }
  return s;
}

}  // namespace

TEST(CameraKinematics, SpawnStandsOnTheFloorAtEyeHeight) {
  const CollisionModel model = corridor();
  const CameraKinematics k(model, 50, 1024);
  const CameraState s = k.spawn(spawnAt(0, 0, 0));
  EXPECT_NEAR(s.floor_z, 0.0, 1e-3);
  EXPECT_NEAR(k.eye(s).z(), 50.0, 1e-3);
  EXPECT_FALSE(k.inSolid(s));
  // Optical frame: z forward along +X, x right along -Y, y down along -Z.
  const Eigen::Isometry3d t = k.cameraToWorld(s);
  EXPECT_TRUE(t.linear().col(2).isApprox(Eigen::Vector3d(1, 0, 0)));
  EXPECT_TRUE(t.linear().col(0).isApprox(Eigen::Vector3d(0, -1, 0)));
  EXPECT_TRUE(t.linear().col(1).isApprox(Eigen::Vector3d(0, 0, -1)));
}

TEST(CameraKinematics, ExactYawAndDisplacementOfEachCandidate) {
  const CollisionModel model = corridor();
  const CameraKinematics k(model, 50, 1024);
  const Config config;
  const CameraState start = k.spawn(spawnAt(0, 0, 90));  // looking along +Y

  const CameraState uw = run(k, start, makeActionSequence("uw", config));
  EXPECT_NEAR(uw.xy.x(), 0.0, 1e-9);
  EXPECT_NEAR(uw.xy.y(), 256.0, 1e-9);
  EXPECT_NEAR(uw.yaw_deg, 90.0, 1e-9);

  const CameraState jq = run(k, start, makeActionSequence("jq", config));
  EXPECT_NEAR(jq.yaw_deg, 180.0, 1e-9);
  EXPECT_EQ(jq.xy, start.xy);
  const CameraState lq = run(k, start, makeActionSequence("lq", config));
  EXPECT_NEAR(lq.yaw_deg, 0.0, 1e-9);
  EXPECT_EQ(lq.xy, start.xy);

  // jw: 57 frames each turning 45/57 deg then moving 256/57 along the new heading,
  // then 40 frames straight at 135 deg.
  const double speed = 256.0 / 57, rate = 45.0 / 57;
  Eigen::Vector2d expected = start.xy;
  for (int i = 1; i <= 57; ++i) {
    const double yaw = (90.0 + i * rate) * M_PI / 180;
    expected += speed * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
  }
  expected += 40 * speed * Eigen::Vector2d(std::cos(135 * M_PI / 180), std::sin(135 * M_PI / 180));
  const CameraState jw = run(k, start, makeActionSequence("jw", config));
  EXPECT_NEAR(jw.yaw_deg, 135.0, 1e-9);
  EXPECT_NEAR((jw.xy - expected).norm(), 0.0, 1e-9);
  const CameraState lw = run(k, start, makeActionSequence("lw", config));
  EXPECT_NEAR(lw.yaw_deg, 45.0, 1e-9);
  EXPECT_NEAR(lw.xy.x(), -jw.xy.x(), 1e-9);  // mirror image about the Y axis
  EXPECT_NEAR(lw.xy.y(), jw.xy.y(), 1e-9);
}

TEST(CameraKinematics, ClimbsAStairAndWalksThroughAWall) {
  const CollisionModel model = corridor();
  const CameraKinematics k(model, 50, 1024);
  const Config config;
  CameraState s = k.spawn(spawnAt(0, 0, 0));
  int in_solid = 0;
  s = run(k, s, makeActionSequence("uw", config), &in_solid);  // x = 256: on the stair
  EXPECT_NEAR(s.floor_z, 16.0, 1e-3);
  EXPECT_EQ(in_solid, 0);
  s = run(k, s, makeActionSequence("uw", config), &in_solid);  // x = 512
  EXPECT_EQ(in_solid, 0);
  s = run(k, s, makeActionSequence("uw", config), &in_solid);  // x = 768: through the wall
  EXPECT_NEAR(s.xy.x(), 768.0, 1e-9);                          // never stopped
  EXPECT_NEAR(s.floor_z, 16.0, 1e-3);                          // height kept inside
  // The hull (half width 15) overlaps the wall for x in (585, 647): 62 units of
  // 256/57 per frame, 13 or 14 frames.
  EXPECT_GE(in_solid, 13);
  EXPECT_LE(in_solid, 14);
}

TEST(CameraKinematics, KeepsHeightIntoATallBlockAndFollowsADrop) {
  const CollisionModel model = corridor();
  const CameraKinematics k(model, 50, 1024);
  const Config config;
  CameraState s = k.spawn(spawnAt(-200, 0, 180));  // looking along -X
  int in_solid = 0;
  s = run(k, s, makeActionSequence("uw", config), &in_solid);  // x = -456: past the block
  EXPECT_NEAR(s.floor_z, 0.0, 1e-3);  // the block was too high to step onto
  EXPECT_GT(in_solid, 20);            // 130 units inside (-415..-285) at 4.5 per frame
  s = run(k, s, makeActionSequence("uw", config));  // x = -712: over the pit
  EXPECT_NEAR(s.floor_z, -128.0, 1e-3);
}

TEST(CameraKinematics, FollowsARamp) {
  const CollisionModel model = corridor();
  const CameraKinematics k(model, 50, 1024);
  CameraState s = k.spawn(spawnAt(0, 400, 0));
  MotionStep step;
  step.forward_units = 4;
  while (s.xy.x() < 164 - 1e-9) s = k.step(s, step);
  // The hull rests on the highest ramp point under its footprint: x = 164 + 15.
  EXPECT_NEAR(s.floor_z, 0.5 * (179 - 100), 0.05);
}
