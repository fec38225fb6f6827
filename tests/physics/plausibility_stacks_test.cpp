// Plausibility (docs/design.md §8a): free boxes stacked on the ground stand and rest, as they do in
// Bullet's and Box2D's stacking demos. A column of ten (scenarios/physics/column.toml) keeps its
// top box on its cell; a 10 x 10 x 10 pile (scenarios/physics/pile.toml) keeps every box at its
// cell's height and comes to rest. Nothing holds them but their contacts: no bonds, no anchor.
#include <gtest/gtest.h>

#include "tests/physics/scene.h"

namespace dw::physics::test {
namespace {

// The scene's bodies are free: no bond, no cluster of more than one, none held by the ground.
void expect_free_bodies(const sim::State& st) {
  EXPECT_TRUE(st.bodies.bonds.empty()) << "bonds at the start";
  for (const sim::Cluster& c : st.bodies.clusters) {
    EXPECT_EQ(c.count, 1u) << "a cluster of several modules";
    EXPECT_FALSE(c.anchored) << "a module held by the ground";
  }
}

// The top box stays within 0.01 across and 0.03 up or down of its cell for 1,000 steps, and no box
// of the column sinks into the one under it or the ground.
TEST(PlausibilityStacks, AColumnOfTenFreeBoxesStands) {
  const scenarios::Scenario s = load_scene("physics/column.toml");
  const sim::ModuleId top = 9;
  const sim::Vec3 cell = s.model->lattice.position(top);
  ASSERT_EQ(cell[2], 9.0f);
  Worst side("top box across from its cell", 0.01f), height("top box up or down from its cell", 0.03f);
  Overlaps overlaps(bullet_world(s), 0.02f);
  run_scene(s, 1000, [&](const sim::State& st, int64_t step) {
    if (step == 0) expect_free_bodies(st);
    const sim::Vec3 at = st.bodies.poses[top].position;
    side.see(across(at, cell), step, [&] { return module_name(top); });
    height.see(updown(at, cell), step, [&] { return module_name(top); });
    overlaps.measure(st, step);
  });
  EXPECT_TRUE(side.within()) << side.report();
  EXPECT_TRUE(height.within()) << height.report();
  EXPECT_TRUE(overlaps.pairs.within()) << overlaps.pairs.report();
  EXPECT_TRUE(overlaps.ground.within()) << overlaps.ground.report();
}

// Every box's centre stays within 0.03 of its cell's height at every step up to 600, and from step
// 200 on every box's kinetic energy is below 1e-4 J (a box drifting at 1.4 cm/s has it).
TEST(PlausibilityStacks, ATenCubedPileOfFreeBoxesRests) {
  const scenarios::Scenario s = load_scene("physics/pile.toml");
  const float mass = bullet_world(s).settings().module_mass;
  const uint32_t n = s.model->module_count();
  ASSERT_EQ(n, 1000u);
  Worst height("centre off its cell's height", 0.03f), energy("kinetic energy from step 200 on (J)", 1e-4f);
  int64_t last_lively = -1;  // the last step a box had 1e-4 J or more
  run_scene(s, 600, [&](const sim::State& st, int64_t step) {
    if (step == 0) expect_free_bodies(st);
    for (sim::ModuleId m = 0; m < n; ++m) {
      height.see(updown(st.bodies.poses[m].position, s.model->lattice.position(m)), step,
                 [&] { return module_name(m); });
      const float e = kinetic_energy(st.bodies.velocities[m], mass);
      if (e >= 1e-4f) last_lively = step;
      if (step >= 200) energy.see(e, step, [&] { return module_name(m); });
    }
  });
  EXPECT_TRUE(height.within()) << height.report();
  EXPECT_TRUE(energy.within()) << energy.report() << "; the last step a box had 1e-4 J: " << last_lively;
}

}  // namespace
}  // namespace dw::physics::test
