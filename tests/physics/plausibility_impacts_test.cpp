// Plausibility (docs/design.md §8a): under impacts nothing passes through anything. In push_wall
// and demolition (scenarios/*.toml), struck modules fly, fall and tumble; at every step of the
// whole run no module reaches more than 0.02 into the ground or below the height a box rests at,
// and no two modules, nor a module and a ball, overlap by more than 0.02, measured as Bullet
// measures (GJK on the rounded boxes, margins included); and the debris comes to rest. First, the
// measures themselves are checked against Bullet's GJK.
#include <gtest/gtest.h>

#include "tests/physics/scene.h"

namespace dw::physics::test {
namespace {

sim::Pose turned(sim::Vec3 at, sim::Vec3 axis, float angle) {
  const float s = std::sin(angle / 2);
  return {.position = at, .orientation = {axis[0] * s, axis[1] * s, axis[2] * s, std::cos(angle / 2)}};
}

// The margin the measures assume is Bullet's, the separating axes' bound is never below GJK's
// depth, and the closed forms for the ground and for spheres agree with the boxes' geometry.
TEST(PlausibilityImpacts, TheMeasuresAgreeWithBulletsGjk) {
  const ContactGraph gjk(ModuleShape::Box, 0.01f);
  const sim::Pose origin{};
  // Boxes whose edges are 0.98 apart diagonally: their cores (0.92 across) 0.06 sqrt 2 apart, less
  // both margins. (GJK reports nothing of a pair whose cores are further apart than both margins
  // and the threshold: edges one size apart diagonally are.)
  EXPECT_NEAR(gjk.distance(origin, {.position = {0.98f, 0.98f, 0}}),
              std::sqrt(2.0f) * (0.98f - 2 * kCore) - 2 * kMargin, 1e-4f);
  EXPECT_NEAR(gjk.distance(origin, {.position = {1, 0, 0}}), 0, 1e-4f) << "faces one size apart touch";
  // Overlapping pairs: the bound is exact face to face, above GJK's depth where a corner leads.
  const sim::Pose pairs[] = {{.position = {0.9f, 0, 0}},
                             {.position = {0.2f, 0.95f, 0.1f}},
                             turned({1.1f, 0, 0}, {0, 0, 1}, 0.785398f),
                             turned({0.7f, 0.7f, 0.3f}, {0.6f, 0, 0.8f}, 0.5f)};
  for (const sim::Pose& q : pairs) {
    const float depth = -gjk.distance(origin, q);
    EXPECT_GT(depth, 0) << q.position[0];
    EXPECT_GE(box_overlap_bound(origin, q), depth - 1e-4f) << q.position[0];
  }
  EXPECT_NEAR(box_overlap_bound(origin, pairs[0]), 0.1f, 1e-5f);
  EXPECT_NEAR(-gjk.distance(origin, pairs[0]), 0.1f, 1e-3f);
  // Turned 45 degrees about y, a box stands on an edge, its rounded corner 0.46 sqrt 2 + 0.04 down.
  EXPECT_NEAR(ground_depth(turned({0, 0, 0.5f}, {0, 1, 0}, 0.785398f), -0.5f), kCore * std::sqrt(2.0f) + kMargin - 1,
              1e-5f);
  EXPECT_NEAR(ground_depth(origin, -0.5f), 0, 1e-6f);
  // A ball of radius 1 one size and a hair off a face, and off an edge.
  EXPECT_NEAR(sphere_depth(origin, {1.5f, 0, 0}, 1), 0, 1e-6f);
  EXPECT_NEAR(sphere_depth(origin, {1.2f, 1.2f, 0}, 1), 1 + kMargin - std::hypot(1.2f - kCore, 1.2f - kCore), 1e-5f);
}

// The scenario's whole run, every step measured.
void expect_nothing_passes_through(const std::string& name) {
  const scenarios::Scenario s = load_scene(name);
  Overlaps overlaps(bullet_world(s), 0.02f);
  int moved = 0;
  run_scene(s, s.steps, [&](const sim::State& st, int64_t step) {
    overlaps.measure(st, step);
    if (step == s.steps - 1)
      for (sim::ModuleId m = 0; m < s.model->module_count(); ++m)
        moved += st.present[m] && updown(st.bodies.poses[m].position, s.model->lattice.position(m)) > 0.5f;
  });
  EXPECT_GT(moved, 3) << name << ": modules fell (the scene is still the one measured)";
  EXPECT_TRUE(overlaps.ground.within()) << name << ": " << overlaps.ground.report();
  EXPECT_TRUE(overlaps.centres.within()) << name << ": " << overlaps.centres.report();
  EXPECT_TRUE(overlaps.pairs.within()) << name << ": " << overlaps.pairs.report();
}

// (The first dynamics: 0.93 into the ground and 1.05 pair overlap. Warm-started at 4 substeps for
// every island: push_wall 0.021 and demolition 0.139, a 200 kg ball at 14 m/s moving 0.058 a
// substep into modules; an island with a faster body now takes more substeps, settings.h.)
TEST(PlausibilityImpacts, PushWallNothingPassesThroughTheGroundOrAnotherBody) {
  expect_nothing_passes_through("push_wall.toml");
}

TEST(PlausibilityImpacts, DemolitionNothingPassesThroughTheGroundOrAnotherBody) {
  expect_nothing_passes_through("demolition.toml");
}

// What came to rest stays at rest: over push_wall's last 150 steps, long after the ball struck (at
// step 30), no module moves a corner more than 0.01. (On the first dynamics, modules lying on
// their sides slid on at 0.12 m/s, their orientation flipping every step.)
TEST(PlausibilityImpacts, PushWallsDebrisComesToRest) {
  const scenarios::Scenario s = load_scene("push_wall.toml");
  const int64_t from = s.steps - 150;
  const uint32_t n = s.model->module_count();
  std::vector<sim::Pose> then(n);
  Worst travel("travel over the last 150 steps", 0.01f);
  int64_t struck = -1;   // the first step a module left its cell
  float ball_speed = 0;  // the most over the last 150 steps
  sim::Pose ball;
  run_scene(s, s.steps, [&](const sim::State& st, int64_t step) {
    for (sim::ModuleId m = 0; m < n && struck < 0; ++m)
      if (st.present[m] && corner_travel({.position = s.model->lattice.position(m)}, st.bodies.poses[m]) > 0.01f)
        struck = step;
    for (sim::ModuleId m = 0; m < n && step >= from; ++m) {
      if (!st.present[m]) continue;
      if (step == from) then[m] = st.bodies.poses[m];
      travel.see(corner_travel(then[m], st.bodies.poses[m]), step, [&] { return module_name(m); });
    }
    ball = st.bodies.prop_poses[0];
    if (step >= from) ball_speed = std::max(ball_speed, length(st.bodies.prop_velocities[0].linear));
  });
  EXPECT_TRUE(travel.within()) << travel.report() << " (the ball struck at step " << struck << "; it ends at "
                               << ball.position[0] << ", " << ball.position[1] << ", " << ball.position[2]
                               << ", at up to " << ball_speed << " m/s over those steps)";
}

}  // namespace
}  // namespace dw::physics::test
