// Plausibility (docs/design.md §8a): one free box against the ground, as Bullet's and Jolt's
// friction and stacking demos try it. A box at rest on a face or lying on a side does not creep
// (scenarios/physics/resting_boxes.toml); a box launched along the ground stops where Coulomb
// friction says (launched_box.toml); a 200 kg box on a 1 kg cube does not press the cube into
// the ground (heavy_on_light.toml).
#include <gtest/gtest.h>

#include "tests/physics/scene.h"

namespace dw::physics::test {
namespace {

// The scene loads as written: the prop lies on its side, turned a quarter turn about x.
TEST(PlausibilityContact, ABoxPropLoadsTurnedAsItsOrientationSays) {
  const scenarios::Scenario s = load_scene("physics/resting_boxes.toml");
  const std::vector<PropSpec>& props = bullet_world(s).settings().props;
  ASSERT_EQ(props.size(), 1u);
  EXPECT_EQ(props[0].shape, ModuleShape::Box);
  const auto z = axes(props[0].pose)[2];  // its z axis lies along -y
  EXPECT_NEAR(z[0], 0, 1e-6f);
  EXPECT_NEAR(z[1], -1, 1e-6f);
  EXPECT_NEAR(z[2], 0, 1e-6f);
  const auto& q = props[0].pose.orientation;
  EXPECT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1, 1e-6f) << "scaled to length 1";
}

// Neither box, the one on its face nor the one on its side, moves any corner more than 0.001 in
// 1,000 steps, nor sinks 0.02 into the ground.
TEST(PlausibilityContact, ABoxAtRestOnAFaceOrASideStaysThere) {
  const scenarios::Scenario s = load_scene("physics/resting_boxes.toml");
  const sim::Pose face{.position = s.model->lattice.position(0)};
  const sim::Pose side = bullet_world(s).settings().props[0].pose;
  Worst on_face("box on a face, travel", 0.001f), on_side("box on a side, travel", 0.001f);
  Overlaps overlaps(bullet_world(s), 0.02f);
  run_scene(s, 1000, [&](const sim::State& st, int64_t step) {
    on_face.see(corner_travel(face, st.bodies.poses[0]), step, [] { return module_name(0); });
    on_side.see(corner_travel(side, st.bodies.prop_poses[0]), step, [] { return std::string("prop 0"); });
    overlaps.measure(st, step);
  });
  EXPECT_TRUE(on_face.within()) << on_face.report();
  EXPECT_TRUE(on_side.within()) << on_side.report();
  EXPECT_TRUE(overlaps.ground.within()) << overlaps.ground.report();
}

// Launched at v = 2 m/s, the box slides v^2 / (2 mu g) and stops there (within 10%), mu the
// friction Bullet gives the pair (btManifoldResult::calculateCombinedFriction: the product of the
// two bodies' frictions, at most 10; the ground's is the modules'). It goes straight, does not
// tip, and then stays where it stopped (no corner moving 0.001 over the last 100 steps).
TEST(PlausibilityContact, ABoxLaunchedAlongTheGroundStopsWhereFrictionSays) {
  const scenarios::Scenario s = load_scene("physics/launched_box.toml");
  const PhysicsSettings& settings = bullet_world(s).settings();
  ASSERT_EQ(s.events.size(), 1u);
  const float v = s.events[0].impulse[0] / settings.module_mass;
  ASSERT_EQ(v, 2.0f);
  const float mu = std::min(settings.friction * settings.friction, 10.0f);
  const float g = -settings.gravity[2];
  const float expected = v * v / (2 * mu * g);
  const int64_t still_from = s.steps - 100;  // it stops in 34 steps; for the last 100 it rests
  float top_speed = 0, off_line = 0, tipped = 0;
  sim::Pose stopped, end;
  Worst creep("travel over the last 100 steps", 0.001f);
  run_scene(s, s.steps, [&](const sim::State& st, int64_t step) {
    const sim::Pose& p = st.bodies.poses[0];
    top_speed = std::max(top_speed, length(st.bodies.velocities[0].linear));
    off_line = std::max(off_line, std::abs(p.position[1]));
    tipped = std::max(tipped, 1 - axes(p)[2][2]);  // 1 - cos of its tilt
    if (step == still_from) stopped = p;
    if (step >= still_from) creep.see(corner_travel(stopped, p), step, [] { return module_name(0); });
    end = p;
  });
  EXPECT_NEAR(top_speed, v, 0.1f * v) << "launched at 2 m/s";
  const float slid = end.position[0] - s.model->lattice.position(0)[0];
  EXPECT_NEAR(slid, expected, 0.1f * expected) << "module 0 slid " << slid << " by step " << s.steps - 1
                                               << ", friction says " << expected << " (mu " << mu << ")";
  EXPECT_TRUE(creep.within()) << creep.report();
  EXPECT_LT(off_line, 0.01f) << "module 0 strayed sideways";
  EXPECT_LT(tipped, 1e-3f) << "module 0 tipped";
}

// The cube's centre never goes more than 0.02 below its rest height in 300 steps, nor its box into
// the ground or the heavy box into it by more than 0.02.
TEST(PlausibilityContact, AHeavyBoxDoesNotPressALightCubeIntoTheGround) {
  const scenarios::Scenario s = load_scene("physics/heavy_on_light.toml");
  const BulletWorld& world = bullet_world(s);
  ASSERT_EQ(world.settings().props.size(), 1u);
  ASSERT_EQ(world.settings().props[0].mass, 200.0f);
  const float rest = s.model->lattice.position(0)[2];
  ASSERT_EQ(rest, world.ground_z() + kHalf);
  Worst sunk("cube's centre below its rest height", 0.02f);
  Overlaps overlaps(world, 0.02f);
  run_scene(s, 300, [&](const sim::State& st, int64_t step) {
    sunk.see(rest - st.bodies.poses[0].position[2], step, [] { return module_name(0); });
    overlaps.measure(st, step);
  });
  EXPECT_TRUE(sunk.within()) << sunk.report();
  EXPECT_TRUE(overlaps.ground.within()) << overlaps.ground.report();
  EXPECT_TRUE(overlaps.pairs.within()) << overlaps.pairs.report() << " (prop 0: the heavy box)";
}

}  // namespace
}  // namespace dw::physics::test
