// The paper's own modules as a user runs them (docs/physics.md, 2-D catoms and Hexanodes): the
// shipped scenarios of climbing catoms and walking Hexanodes, and a pile of free discs, measured
// as the plausibility suite measures its scenes: nothing sinks into anything, what rests stays,
// and the runs are the same on any thread count.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "physics/contact_graph.h"
#include "sim/session.h"
#include "tests/physics/scene.h"

namespace dw::physics::test {
namespace {

constexpr float kRow = 0.8660254f;  // sqrt(3)/2

float gap(const sim::Vec3& a, const sim::Vec3& b) { return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }

// Runs a scenario for `steps` on `threads`, measuring at every step the deepest overlap of two
// modules (GJK on the scenario's shapes, margins included) and of a module with the ground (a
// disc's or a prism's lowest point is half a size under its centre, for any turn they take);
// returns the hashes of every step.
std::vector<uint64_t> run_measured(const scenarios::Scenario& s, int64_t steps, unsigned threads, Worst& pairs,
                                   Worst& ground, const std::function<void(const sim::State&, int64_t)>& look = {}) {
  const BulletWorld& world = bullet_world(s);
  const ContactGraph shapes(world.shape(), world.settings().contact_threshold);
  std::vector<uint64_t> hashes;
  run_scene(
      s, steps,
      [&](const sim::State& st, int64_t step) {
        hashes.push_back(sim::hash_state(st).whole());
        const sim::Bodies& b = st.bodies;
        for (sim::ModuleId m = 0; m < b.poses.size(); ++m) {
          if (!st.present[m]) continue;
          ground.see(world.ground_z() - (b.poses[m].position[2] - 0.5f), step, [&] { return module_name(m); });
          for (sim::ModuleId o = m + 1; o < b.poses.size(); ++o)
            if (st.present[o] && gap(b.poses[m].position, b.poses[o].position) < 1.2f)
              pairs.see(-shapes.distance(b.poses[m], b.poses[o]), step,
                        [&] { return module_name(m) + " and " + module_name(o); });
        }
        if (look) look(st, step);
      },
      threads);
  return hashes;
}

// The last state of `steps` steps run on 1 and on 2 threads, checking on the way that no module
// passes more than 0.02 into another or into the ground, and that both runs' hashes are equal.
std::array<sim::State, 2> last_states_on_1_and_2_threads(const scenarios::Scenario& s, int64_t steps) {
  std::array<sim::State, 2> last;
  std::vector<uint64_t> hashes[2];
  for (unsigned threads : {1u, 2u}) {
    Worst pairs("pair penetration", 0.02f), ground("depth into the ground", 0.02f);
    hashes[threads - 1] = run_measured(s, steps, threads, pairs, ground, [&](const sim::State& st, int64_t step) {
      if (step == steps - 1) last[threads - 1] = st;
    });
    EXPECT_TRUE(pairs.within()) << pairs.report();
    EXPECT_TRUE(ground.within()) << ground.report();
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  return last;
}

// Two catoms climb the sides of a pyramid of catoms latched to the ground, against gravity, to
// its top row (row 4) in four pivots each; the pyramid stands exactly still; no catom passes
// into another or into the ground on the way; 1 and 2 threads give the same hashes.
TEST(PlausibilityHex, CatomsClimbAPyramidAgainstGravityWithoutPassingIntoIt) {
  const scenarios::Scenario s = load_scene("catoms2d_climb.toml");
  EXPECT_EQ(bullet_world(s).shape(), ModuleShape::Disc);
  for (const sim::State& last : last_states_on_1_and_2_threads(s, 80)) {
    for (sim::ModuleId m = 1; m < 8; ++m)  // the pyramid's bottom row, and every module above it
      EXPECT_EQ(last.bodies.poses[m].position, s.model->lattice.position(m)) << m;
    for (sim::ModuleId m = 9; m < s.model->module_count(); ++m) {
      if (last.present[m]) {
        EXPECT_EQ(last.bodies.poses[m].position, s.model->lattice.position(m)) << m;
      }
    }
    // The climbers stand on the top row, at its two ends (columns 2 and 6: x = 2 and 6).
    EXPECT_LT(gap(last.bodies.poses[0].position, {2, 0, 4 * kRow}), 1e-3f);
    EXPECT_LT(gap(last.bodies.poses[8].position, {6, 0, 4 * kRow}), 1e-3f);
  }
}

// Three free discs piled as pipes are (two on the ground, one on both) stand for 600 steps (10 s):
// each stays within 0.05 of its cell (the two below creep apart by 0.04 until the pile sleeps:
// 0.02 is passed), none sinks into another or the ground by more than 0.01, and the one on top
// is still on top.
TEST(PlausibilityHex, APileOfFreeDiscsStands) {
  const scenarios::Scenario s = load_scene("physics/disc_pile.toml");
  Worst pairs("pair penetration", 0.01f), ground("depth into the ground", 0.01f), drift("drift from its cell", 0.05f);
  run_measured(s, 600, 1, pairs, ground, [&](const sim::State& st, int64_t step) {
    for (sim::ModuleId m = 0; m < s.model->module_count(); ++m) {
      if (st.present[m])
        drift.see(gap(st.bodies.poses[m].position, s.model->lattice.position(m)), step, [&] { return module_name(m); });
    }
  });
  EXPECT_TRUE(pairs.within()) << pairs.report();
  EXPECT_TRUE(ground.within()) << ground.report();
  EXPECT_TRUE(drift.within()) << drift.report();
}

// The pyramid of six free discs (scenarios/physics/disc_pyramid.toml) as Box2D's and Bullet's
// rolling-friction demos check theirs: it slumps (the solver does not hold it as friction would),
// then rolling resistance brings every disc to rest by step 400, and each stays within 0.01 of
// where it lay then up to step 600; no disc passes more than 0.02 into another or the ground, and
// 1 and 2 threads give the same hashes. The same pile without rolling resistance
// (rolling_friction = 0) still rolls apart at step 600: what holds it is the setting.
TEST(PlausibilityHex, APyramidOfFreeDiscsComesToRestAndStays) {
  constexpr int64_t kSettled = 400, kSteps = 600;
  const scenarios::Scenario s = load_scene("physics/disc_pyramid.toml");
  ASSERT_EQ(bullet_world(s).settings().rolling_friction, 0.02f);  // the default
  const auto travel_after_settling = [&](const scenarios::Scenario& scene, unsigned threads) {
    Worst pairs("pair penetration", 0.02f), ground("depth into the ground", 0.02f);
    Worst travel("travel after step " + std::to_string(kSettled), 0.01f);
    std::vector<sim::Vec3> settled;
    const std::vector<uint64_t> hashes =
        run_measured(scene, kSteps, threads, pairs, ground, [&](const sim::State& st, int64_t step) {
          if (step == kSettled)
            for (sim::ModuleId m = 0; m < st.bodies.poses.size(); ++m) settled.push_back(st.bodies.poses[m].position);
          if (step <= kSettled) return;
          for (sim::ModuleId m = 0; m < settled.size(); ++m) {
            if (st.present[m])
              travel.see(gap(st.bodies.poses[m].position, settled[m]), step, [&] { return module_name(m); });
          }
        });
    EXPECT_TRUE(pairs.within()) << pairs.report();
    EXPECT_TRUE(ground.within()) << ground.report();
    return std::pair(travel, hashes);
  };
  const auto [one, one_hashes] = travel_after_settling(s, 1);
  const auto [two, two_hashes] = travel_after_settling(s, 2);
  EXPECT_TRUE(one.within()) << one.report();
  EXPECT_TRUE(two.within()) << two.report();
  EXPECT_EQ(one_hashes, two_hashes);
  EXPECT_EQ(one_hashes.size(), size_t(kSteps));

  std::ifstream file(s.path);
  std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const std::string physics = "[physics]\n";
  ASSERT_NE(text.find(physics), std::string::npos);
  text.insert(text.find(physics) + physics.size(), "rolling_friction = 0\n");
  auto loaded = scenarios::load_scenario_text(s.path, text);
  ASSERT_TRUE(std::holds_alternative<scenarios::Scenario>(loaded)) << std::get<std::string>(loaded);
  const auto [free_rolling, hashes] = travel_after_settling(std::get<scenarios::Scenario>(loaded), 1);
  EXPECT_GT(free_rolling.value(), 1.0f) << free_rolling.report();
}

// Two Hexanodes walk round a patch of twelve on the ground the opposite ways, turning about shared
// edges, and meet head on under it: no prism passes into another, the patch stays put, each walker
// makes its turns until they touch (the first four, the second three, 11 steps behind), and then
// both stand still beside each other; 1 and 2 threads give the same hashes.
TEST(PlausibilityHex, HexanodesWalkRoundAPatchWithoutPassingIntoIt) {
  const scenarios::Scenario s = load_scene("hexanodes_walk.toml");
  EXPECT_EQ(bullet_world(s).shape(), ModuleShape::HexPrism);
  const int rolls = s.model->column("rolls");
  ASSERT_GE(rolls, 0);
  const size_t vars = s.model->universe.variables.size();
  for (const sim::State& last : last_states_on_1_and_2_threads(s, 200)) {
    for (sim::ModuleId m = 0; m < s.model->module_count(); ++m) {
      if (last.present[m] && m != 25 && m != 30) {
        EXPECT_EQ(last.bodies.poses[m].position, s.model->lattice.position(m)) << m;
      }
    }
    EXPECT_EQ(last.values[25 * vars + size_t(rolls)], 4);
    EXPECT_EQ(last.values[30 * vars + size_t(rolls)], 3);
    // Side by side under the patch (row 1, columns 3 and 4): one module apart along x.
    EXPECT_LT(gap(last.bodies.poses[25].position, {3.5f, kRow, 0}), 1e-3f);
    EXPECT_LT(gap(last.bodies.poses[30].position, {4.5f, kRow, 0}), 1e-3f);
  }
}

// The scenario's watchpoint, walkers_meet (`modules(a b)`: two neighbours that have both turned),
// logs the walkers touching: none before step 58, where the second arrives beside the first, and
// from there on at every step both orders of the two walkers, and nothing else.
TEST(PlausibilityHex, TheHexanodesWatchpointLogsTheWalkersMeetingFromStep58) {
  const scenarios::Scenario s = load_scene("hexanodes_walk.toml");
  ASSERT_EQ(s.model->watches.size(), 1u);
  sim::Session run(*s.model, *s.world, {.threads = 1});
  run.run_until(200);
  const sim::MatchList& found = run.matches(0);
  ASSERT_EQ(found.size(), size_t(2 * (200 - 58)));
  for (size_t i = 0; i < found.size(); ++i) {
    EXPECT_EQ(found.t[i], 58 + int64_t(i / 2)) << i;
    const sim::ModuleId a = found.slots[2 * i], b = found.slots[2 * i + 1];
    EXPECT_EQ(i % 2 == 0 ? std::pair(a, b) : std::pair(b, a), std::pair(sim::ModuleId(25), sim::ModuleId(30))) << i;
  }
}

}  // namespace
}  // namespace dw::physics::test
