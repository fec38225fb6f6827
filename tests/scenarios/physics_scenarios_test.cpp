// The scenarios with a Bullet world (scenarios/*.toml with [physics]): determinism and rollback
// with physics (docs/design.md §7), the wall that breaks, the §I watchpoint on sliding modules, and the
// physics variants of leader election and token ring matching their static lattices exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <sstream>

#include "physics/bullet_world.h"
#include "scenarios/scenario.h"
#include "sim/body_slices.h"
#include "sim/session.h"
#include "sim/state.h"
#include "tests/sim/run_trail.h"
#include "tests/sim/thread_ranks.h"

namespace dw::scenarios {
namespace {

Scenario load_file(const std::string& name, ScenarioOverrides overrides = {}) {
  auto loaded = load_scenario(std::string(DWATCH_SCENARIOS_DIR) + "/" + name, overrides);
  if (auto* e = std::get_if<std::string>(&loaded)) ADD_FAILURE() << *e;
  return std::move(std::get<Scenario>(loaded));
}

using sim::test::Trail;
constexpr auto matches_of = sim::test::flat_matches;

Trail straight(const std::string& name, unsigned threads, int64_t steps, ScenarioOverrides overrides = {}) {
  Scenario s = load_file(name, overrides);
  sim::Session run(*s.model, *s.world, {.threads = threads});
  Trail t;
  run.run_until(steps,
                [&](const sim::State& st, const sim::StepOutput&) { t.hashes.push_back(sim::hash_state(st).whole()); });
  t.matches = matches_of(run);
  return t;
}

TEST(PushWall, TheWallBreaksModulesFallAndBothWatchpointsFire) {
  Scenario s = load_file("push_wall.toml");
  sim::Session run(*s.model, *s.world, {.threads = 1});
  const size_t bonds_before = run.state().bodies.bonds.size();
  run.run_until(600);
  const sim::Bodies& b = run.state().bodies;
  EXPECT_LT(b.bonds.size(), bonds_before) << "bonds broke";
  int fell = 0;
  for (sim::ModuleId m = 0; m < s.model->module_count(); ++m)
    fell += b.poses[m].position[2] < s.model->lattice.position(m)[2] - 0.9f;
  EXPECT_GE(fell, 3) << "modules fell";
  EXPECT_GT(b.clusters.size(), 2u) << "the wall came apart";
  EXPECT_GT(run.matches(0).size(), 0u) << "torn_off";
  EXPECT_GT(run.matches(1).size(), 0u) << "both_moving";
  EXPECT_GT(run.matches(1).t.front(), 20) << "nothing moves before the ball arrives";
}

TEST(PushWall, SeekingBackAndForthEqualsTheUninterruptedRunHashForHash) {
  const Trail uninterrupted = straight("push_wall.toml", 1, 600);
  ASSERT_EQ(uninterrupted.hashes.size(), 600u);

  Scenario s = load_file("push_wall.toml");
  sim::Session run(*s.model, *s.world, {.threads = 1, .history_bytes = 4 << 20});
  run.run_until(600);
  EXPECT_GT(run.keyframe_interval(), 1);
  for (int64_t t : {200, 599, 17, 450, 451, 0, 333}) {
    ASSERT_TRUE(run.seek(t));
    ASSERT_EQ(run.hash().whole(), uninterrupted.hashes[size_t(t)]) << "step " << t;
  }
  EXPECT_EQ(matches_of(run), uninterrupted.matches);
}

// Over ranks, every rank holds the bodies whole and alike, and its keyframes keep only its slice
// of them (sim/body_slices.h): seeks put them back together from all the ranks' slices, with one
// process's hashes and matches, and the ranks' histories add up to about one process's.
TEST(PushWall, OverRanksKeyframesKeepASliceOfTheBodiesAndSeeksEqualOneProcess) {
  // Over ranks watchpoints run distributed over consistent states (docs/design.md §12).
  const ScenarioOverrides consistent{.algorithm = watch::Algorithm::Distributed, .states = watch::States::Consistent};
  const Trail uninterrupted = straight("push_wall.toml", 1, 300, consistent);
  Scenario s = load_file("push_wall.toml", consistent);
  sim::Session alone(*s.model, *s.world, {.threads = 1, .history_bytes = 64 << 20});
  const size_t keyframe_zero = alone.history_bytes();  // (how many follow depends on the copies' time)
  const size_t bodies_zero = sim::BodySlice(alone.state().bodies, 0, 1).size();
  alone.run_until(300);
  for (int ranks : {2, 3}) {
    const auto seen = sim::on_ranks(ranks, [&](sim::RankExchange& r) {
      Scenario s = load_file("push_wall.toml", consistent);
      sim::Session run(*s.model, *s.world, {.threads = 1, .history_bytes = 64 << 20, .ranks = &r});
      const size_t bytes = run.history_bytes();
      run.run_until(300);
      std::vector<uint64_t> hashes;
      for (int64_t t : {200, 17, 299, 150, 151, 0}) {
        EXPECT_TRUE(run.seek(t));
        hashes.push_back(run.hash().whole());
      }
      return std::tuple(hashes, bytes, matches_of(run));
    });
    size_t history = 0;
    for (const auto& [hashes, bytes, matches] : seen) {
      EXPECT_EQ(hashes,
                (std::vector<uint64_t>{uninterrupted.hashes[200], uninterrupted.hashes[17], uninterrupted.hashes[299],
                                       uninterrupted.hashes[150], uninterrupted.hashes[151], uninterrupted.hashes[0]}))
          << ranks << " ranks";
      EXPECT_EQ(matches, uninterrupted.matches);
      history += bytes;
    }
    // Keyframe 0 over the ranks: the bodies once, in slices, and each rank at most one process's
    // rest (it holds some of it whole: presence, the graph). Measured: 14,879 bytes on 2 ranks
    // and 17,263 on 3, against one process's 9,239, of which the bodies are 1,611 (the wall at
    // rest keeps no pose: sim/paged_array.h). That the slices split the bodies, and not each
    // rank's whole, BodySlices' tests show: here the bodies are too small a part to tell.
    EXPECT_LE(history, size_t(ranks) * (keyframe_zero - bodies_zero) + bodies_zero + 64 * size_t(ranks))
        << ranks << " ranks, one process " << keyframe_zero << " of which bodies " << bodies_zero;
  }
}

// Keyframes keep the bodies in chunks shared with the keyframe before where their bytes did not
// change (sim/body_slices.h): the history of a lattice resting latched to the ground holds its
// bodies once, and seeks give the states of the run, in one process and over ranks.
TEST(Keyframes, AStillWorldsHistoryHoldsItsBodiesOnce) {
  const std::string text =
      "steps = 12\n[lattice]\nkind = \"cubic\"\nsize = [12, 12, 12]\n[[program]]\nname = \"body_sense\"\n"
      "[physics]\nenabled = true\n";
  const auto load = [&] {
    auto loaded = load_scenario_text("still.toml", text);
    if (auto* e = std::get_if<std::string>(&loaded)) ADD_FAILURE() << *e;
    return std::move(std::get<Scenario>(loaded));
  };
  Scenario straight_run = load();
  sim::Session plain(*straight_run.model, *straight_run.world, {.threads = 1, .history_bytes = 0});
  std::vector<uint64_t> hashes;
  plain.run_until(12,
                  [&](const sim::State& st, const sim::StepOutput&) { hashes.push_back(sim::hash_state(st).whole()); });
  const size_t bodies = sim::BodySlice(plain.state().bodies, 0, 1).size();

  for (int ranks : {1, 2}) {
    const auto seen = sim::on_ranks(ranks, [&](sim::RankExchange& r) {
      Scenario s = load();
      sim::Session run(*s.model, *s.world,
                       {.threads = 1,
                        .history_bytes = 256 << 20,
                        .ranks = &r,
                        .keyframe_time_share = std::numeric_limits<double>::infinity()});
      const size_t keyframe_zero = run.history_bytes();
      run.run_until(12);
      const size_t keyframes = run.keyframes(), later = run.history_bytes() - keyframe_zero;
      std::vector<uint64_t> at;
      for (int64_t t : {11, 3, 0, 7}) {
        EXPECT_TRUE(run.seek(t));
        at.push_back(run.hash().whole());
      }
      return std::tuple(keyframes, keyframe_zero, later, at);
    });
    for (const auto& [keyframes, keyframe_zero, later, at] : seen) {
      EXPECT_EQ(at, (std::vector<uint64_t>{hashes[11], hashes[3], hashes[0], hashes[7]})) << ranks << " ranks";
      // Keyframe 0 holds this rank's share of the bodies; the later ones none of them.
      EXPECT_EQ(keyframes, 12u);
      EXPECT_GT(keyframe_zero, bodies / size_t(ranks));
      EXPECT_LT(later, (keyframes - 1) * (keyframe_zero - bodies / size_t(ranks)) + 4096) << ranks << " ranks";
    }
  }
}

// A push and a removal made during a session with physics equal the same interventions
// scheduled as [[event]]s, on 1 and 2 threads.
TEST(PushWall, InterventionsEqualTheScheduledEvents) {
  for (unsigned threads : {1u, 2u}) {
    Scenario s = load_file("push_wall.toml");
    sim::Session run(*s.model, *s.world, {.threads = threads});
    run.run_until(80);
    ASSERT_TRUE(run.seek(30));
    ASSERT_EQ(run.intervene({.kind = sim::Intervention::Kind::Push, .module = 5, .impulse = {0, 40, 0}}), "");
    run.run_until(50);
    ASSERT_EQ(run.intervene({.kind = sim::Intervention::Kind::Remove, .module = 52}), "");
    run.run_until(120);

    Scenario again = load_file("push_wall.toml");
    std::vector<uint64_t> hashes;
    sim::Session straight_run(*again.model, *again.world, {.threads = threads, .events = run.interventions()});
    straight_run.run_until(
        120, [&](const sim::State& st, const sim::StepOutput&) { hashes.push_back(sim::hash_state(st).whole()); });
    Trail untouched = straight("push_wall.toml", threads, 120);
    EXPECT_EQ(hashes[30], untouched.hashes[30]);
    // The wall is anchored: the push shows once the ball has broken it loose, before the removal.
    EXPECT_NE(hashes[50], untouched.hashes[50]) << "the push changed the run";
    for (int64_t t = 0; t < 120; t += 3) {
      ASSERT_TRUE(run.seek(t));
      ASSERT_EQ(run.hash().whole(), hashes[size_t(t)]) << "step " << t << ", " << threads << " threads";
    }
    EXPECT_FALSE(run.seen_present()[52]);
    EXPECT_EQ(matches_of(run), matches_of(straight_run));
  }
}

TEST(PushWall, SameSeedSameHashesOnAnyThreadCount) {
  const Trail one = straight("push_wall.toml", 1, 200);
  EXPECT_EQ(straight("push_wall.toml", 1, 200).hashes, one.hashes);
  const Trail two = straight("push_wall.toml", 2, 200);
  EXPECT_EQ(two.hashes, one.hashes);
  EXPECT_EQ(two.matches, one.matches);
}

// reconfigure_large.toml on an n^3 block: the shipped file with its lattice (and, with
// alternate, the program's coordination) rewritten.
Scenario surface_flow(int n, bool alternate = false) {
  std::ifstream in(std::string(DWATCH_SCENARIOS_DIR) + "/reconfigure_large.toml");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  std::string lattice = "[lattice]\nkind = \"cubic\"\nsize = [" + std::to_string(n) + ", " + std::to_string(n) + ", " +
                        std::to_string(n) + "]\n";
  for (int y = 5; y < n; y += 10)
    lattice += "[[lattice.empty]]\nfrom = [0, " + std::to_string(y) + ", " + std::to_string(n - 1) + "]\nto = [" +
               std::to_string(n - 1) + ", " + std::to_string(y) + ", " + std::to_string(n - 1) + "]\n";
  const size_t from = text.find("\n[lattice]") + 1, to = text.find("\n[[program]]") + 1;
  text.replace(from, to - from, lattice + "\n");
  const std::string program = "name = \"surface_flow\"\n";
  if (alternate) text.replace(text.find(program), program.size(), program + "alternate = 1\n");
  auto loaded = load_scenario_text("reconfigure_" + std::to_string(n) + ".toml", text);
  if (auto* e = std::get_if<std::string>(&loaded)) ADD_FAILURE() << *e;
  return std::move(std::get<Scenario>(loaded));
}

// Two modules of the top layer asking for one cell at one step are caught: the watchpoint's a and
// c are diagonal to each other on the layer, ask for the same cell (the one at +x of one and +y
// of the other), and b is the module behind that cell on the diagonal. With alternate = 1 no two
// modules ever ask for one cell at once.
// Every same_cell match of a surface_flow run on a layer at height `layer`, lattice `size_x` wide:
// a and c ask for one cell at its step, sit diagonal to each other on the layer, and b is the
// module behind that cell on the diagonal. Returns the matches checked.
size_t expect_same_cell_matches(sim::Session& run, const sim::Model& model, long layer, long size_x) {
  const sim::MatchList& found = run.matches(0);
  const uint32_t vars = model.variable_count();
  const auto cell = [&](sim::ModuleId m) {
    const auto& p = run.state().bodies.poses[m].position;
    return std::array<long, 3>{std::lround(p[0]), std::lround(p[1]), std::lround(p[2])};
  };
  for (size_t i = 0; i < found.size(); ++i) {
    EXPECT_TRUE(run.seek(found.t[i]));
    const sim::ModuleId a = found.slots[3 * i], b = found.slots[3 * i + 1], c = found.slots[3 * i + 2];
    const std::vector<int64_t> values = run.whole_values(run.state());
    const int64_t target = values[size_t(a) * vars];
    EXPECT_GE(target, 0);
    EXPECT_EQ(values[size_t(c) * vars], target) << "match at t=" << found.t[i];
    const auto ca = cell(a), cb = cell(b), cc = cell(c);
    EXPECT_EQ(ca[2], layer);
    EXPECT_EQ(cc[2], layer);
    EXPECT_EQ(std::abs(ca[0] - cc[0]), 1);
    EXPECT_EQ(ca[0] - cc[0], cc[1] - ca[1]) << "diagonal";
    const std::array<long, 3> behind{std::min(ca[0], cc[0]), std::min(ca[1], cc[1]), layer};
    EXPECT_EQ(cb, behind);
    EXPECT_EQ(target, (behind[0] + 1) + size_x * (behind[1] + 1)) << "the cell ahead on the diagonal";
  }
  return found.size();
}

TEST(SurfaceFlow, TwoModulesHeadingForOneCellAreCaughtWithTheModuleBehindIt) {
  Scenario s = surface_flow(20);
  sim::Session run(*s.model, *s.world, {.threads = 1, .history_bytes = 64 << 20});
  run.run_until(100);
  EXPECT_GT(expect_same_cell_matches(run, *s.model, 19, 20), 0u);

  Scenario fixed = surface_flow(20, true);
  sim::Session calm(*fixed.model, *fixed.world, {.threads = 1});
  calm.run_until(100);
  EXPECT_EQ(calm.matches(0).size(), 0u);
  int moved = 0;  // and yet the holes flowed
  for (sim::ModuleId m = 0; m < fixed.model->module_count(); ++m)
    moved += calm.state().present[m] && calm.state().bodies.poses[m].position != fixed.model->lattice.position(m);
  EXPECT_GT(moved, 100);
}

// After many lattice moves, the contact graph among modules at rest is exactly the lattice's:
// two of them touch if and only if their cells share a face.
// Among modules at rest, a contact for exactly the pairs whose cells share a face; returns those.
uint64_t expect_rest_contacts_are_faces(const sim::State& st) {
  const sim::Bodies& b = st.bodies;
  uint64_t faces_found = 0;
  for (sim::ModuleId m = 0; m < b.poses.size(); ++m)
    for (sim::ModuleId o = m + 1; o < b.poses.size(); ++o) {
      if (!st.present[m] || !st.present[o] || b.moving(m) || b.moving(o)) continue;
      const auto& p = b.poses[m].position;
      const auto& q = b.poses[o].position;
      const float d = std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]);
      const bool faces = std::abs(d - 1) < 1e-4f;
      EXPECT_EQ(st.graph->adjacent(m, o), faces) << m << " and " << o;
      faces_found += faces;
    }
  return faces_found;
}

TEST(SurfaceFlow, ModulesAtRestTouchExactlyTheirFaceNeighboursAfterTheMoves) {
  Scenario s = surface_flow(12);
  sim::Session run(*s.model, *s.world, {.threads = 2});
  run.run_until(60);
  EXPECT_GT(expect_rest_contacts_are_faces(run.state()), 3u * 12 * 12 * 11 - 200);
}

// Many modules setting off and arriving at once: the same hashes every step on 1 and 2 threads,
// and through seeks back and forth.
TEST(SurfaceFlow, SameHashesOnAnyThreadCountAndThroughSeeks) {
  const auto trail = [](unsigned threads) {
    Scenario s = surface_flow(12);
    sim::Session run(*s.model, *s.world, {.threads = threads});
    Trail t;
    run.run_until(
        80, [&](const sim::State& st, const sim::StepOutput&) { t.hashes.push_back(sim::hash_state(st).whole()); });
    t.matches = matches_of(run);
    return t;
  };
  const Trail one = trail(1);
  EXPECT_EQ(trail(2).hashes, one.hashes);
  Scenario s = surface_flow(12);
  sim::Session run(*s.model, *s.world, {.threads = 2, .history_bytes = 8 << 20});
  run.run_until(80);
  for (int64_t t : {40, 79, 3, 61, 62, 0, 25}) {
    ASSERT_TRUE(run.seek(t));
    ASSERT_EQ(run.hash().whole(), one.hashes[size_t(t)]) << "step " << t;
  }
  run.run_until(80);
  EXPECT_EQ(matches_of(run), one.matches);
}

// Smart Blocks on a plane: the same bug caught on the square2d floor of smart_blocks_flow.toml.
TEST(SmartBlocksFlow, TwoBlocksHeadingForOneCellAreCaught) {
  Scenario s = load_file("smart_blocks_flow.toml");
  EXPECT_EQ(s.world->moves(), true);
  sim::Session run(*s.model, *s.world, {.threads = 2, .history_bytes = 16 << 20});
  run.run_until(200);
  // On the square floor, blocks at rest touch exactly their four (or fewer) face neighbours.
  EXPECT_GT(expect_rest_contacts_are_faces(run.state()), 2u * 15 * 16 - 100);
  EXPECT_GT(expect_same_cell_matches(run, *s.model, 0, 16), 0u);
  // The same hashes on 1 and 2 threads, and through the seeks above and more.
  const Trail one = straight("smart_blocks_flow.toml", 1, 200);
  EXPECT_EQ(straight("smart_blocks_flow.toml", 2, 200).hashes, one.hashes);
  for (int64_t t : {150, 7, 199, 61, 62}) {
    ASSERT_TRUE(run.seek(t));
    ASSERT_EQ(run.hash().whole(), one.hashes[size_t(t)]) << "step " << t;
  }
}

// Catoms 3D rolling over an fcc block (pivots, in Lua) while the election runs: each of the three
// top catoms ends five sites along, exactly on its lattice site, touching exactly the catoms one
// site away from it (the two under it at the block's edge); the same hashes on 1 and 2 threads and through seeks; the
// election's bug still caught.
TEST(CatomsRoll, ThreeCatomsRollFiveSitesAndTouchWhatTheLatticeSays) {
  const Trail one = straight("catoms3d_roll.toml", 1, 80);
  EXPECT_EQ(straight("catoms3d_roll.toml", 2, 80).hashes, one.hashes);
  EXPECT_GT(one.matches[0].size(), 0u) << "two_leaders";

  Scenario s = load_file("catoms3d_roll.toml");
  sim::Session run(*s.model, *s.world, {.threads = 2, .history_bytes = 16 << 20});
  run.run_until(80);
  const sim::State& st = run.state();
  for (const sim::ModuleId roller : {108u, 120u, 132u}) {
    const sim::ModuleId site = roller + 5;  // five sites along x on the top layer
    const sim::Vec3& at = s.model->lattice.position(site);
    EXPECT_EQ(st.bodies.poses[roller].position, at) << roller;
    std::vector<sim::ModuleId> expected;
    for (sim::ModuleId o = 0; o < s.model->module_count(); ++o) {
      const sim::Vec3& p = st.bodies.poses[o].position;
      if (o != roller && st.present[o] && std::abs(std::hypot(p[0] - at[0], p[1] - at[1], p[2] - at[2]) - 1) < 1e-3f)
        expected.push_back(o);
    }
    EXPECT_EQ(expected.size(), 2u) << "the two under it, at the block's edge";
    EXPECT_EQ(std::vector<sim::ModuleId>(st.graph->neighbors(roller).begin(), st.graph->neighbors(roller).end()),
              expected)
        << roller;
  }
  for (int64_t t : {30, 79, 5, 41, 42, 0}) {
    ASSERT_TRUE(run.seek(t));
    ASSERT_EQ(run.hash().whole(), one.hashes[size_t(t)]) << "step " << t;
  }
}

TEST(Slide, ModulesSettingOffOneStepApartMatchTheSectionIWatchpoint) {
  Scenario s = load_file("slide.toml");
  sim::Session run(*s.model, *s.world, {.threads = 1});
  run.run_until(300);
  // The head (15) sets off at step 1, once it has heard that nothing is ahead; each of the others
  // one step after the one ahead of it. So exactly the three pairs (a sets off, b right behind it
  // within four steps) match, each at the step a sets off.
  const auto matches = matches_of(run)[0];
  EXPECT_EQ(matches, (std::vector<int64_t>{1, 15, 14, 2, 14, 13, 3, 13, 12})) << "t, a, b per match";
  // The head of the train ends at the stop, the others right behind it, on the top row.
  const sim::Bodies& b = run.state().bodies;
  EXPECT_TRUE(b.movers.empty());
  std::vector<float> xs;
  for (sim::ModuleId id = 12; id < 16; ++id) {
    EXPECT_NEAR(b.poses[id].position[2], 1.0f, 1e-4f);
    xs.push_back(b.poses[id].position[0]);
  }
  EXPECT_EQ(xs, (std::vector<float>{8, 9, 10, 11}));
}

TEST(Slide, AGapOfFourStepsNeverSetsNeighboursOffTogether) {
  // The same file with gap = 4.
  auto text = [] {
    std::ifstream in(std::string(DWATCH_SCENARIOS_DIR) + "/slide.toml");
    std::stringstream ss;
    ss << in.rdbuf();
    std::string t = ss.str();
    t.replace(t.find("\ngap = 0"), 8, "\ngap = 4");
    return t;
  }();
  auto loaded = load_scenario_text("slide_gap4.toml", text);
  ASSERT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
  Scenario& safe = std::get<Scenario>(loaded);
  sim::Session run(*safe.model, *safe.world, {.threads = 1});
  run.run_until(400);
  EXPECT_EQ(run.matches(0).size(), 0u);
  EXPECT_EQ(run.state().bodies.poses[15].position[0], 11.0f) << "and the train still arrives";
}

void expect_same_matches_as_static(const std::string& physics_file, const std::string& static_file, int64_t steps) {
  for (unsigned threads : {1u, 2u}) {
    Scenario p = load_file(physics_file), s = load_file(static_file);
    sim::Session pr(*p.model, *p.world, {.threads = threads}), sr(*s.model, *s.world, {.threads = threads});
    // Run through every pause: the matches of the whole run.
    while (pr.run_until(steps)) {
    }
    while (sr.run_until(steps)) {
    }
    EXPECT_EQ(pr.current() + 1, steps);
    ASSERT_FALSE(matches_of(sr)[0].empty());
    EXPECT_EQ(matches_of(pr), matches_of(sr)) << physics_file << " on " << threads << " threads";
    for (sim::ModuleId m = 0; m < p.model->module_count(); ++m)
      ASSERT_TRUE(std::ranges::equal(pr.state().graph->neighbors(m), s.model->lattice.graph->neighbors(m))) << m;
  }
}

TEST(PhysicsVariants, LeaderElectionMatchesExactlyTheStaticLattice) {
  expect_same_matches_as_static("leader_election_physics.toml", "leader_election.toml", 200);
}

TEST(PhysicsVariants, Catoms3dLeaderElectionMatchesExactlyTheStaticFccLattice) {
  Scenario p = load_file("catoms3d_leader_election.toml");
  std::ifstream in(std::string(DWATCH_SCENARIOS_DIR) + "/catoms3d_leader_election.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::string without = text.str();
  without.erase(without.find("[physics]\nenabled = true\n"), 26);
  auto loaded = load_scenario_text("catoms3d_static.toml", without);
  ASSERT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
  Scenario& s = std::get<Scenario>(loaded);
  ASSERT_TRUE(s.model->lattice.spec.kind == sim::LatticeKind::Fcc);
  sim::Session pr(*p.model, *p.world, {.threads = 2}), sr(*s.model, *s.world, {.threads = 2});
  ASSERT_FALSE(pr.state().bodies.empty()) << "the physics one has bodies";
  ASSERT_TRUE(sr.state().bodies.empty());
  while (pr.run_until(100)) {
  }
  while (sr.run_until(100)) {
  }
  ASSERT_FALSE(matches_of(sr)[0].empty()) << "the bug shows on the fcc lattice";
  EXPECT_EQ(matches_of(pr), matches_of(sr));
  for (sim::ModuleId m = 0; m < p.model->module_count(); ++m)
    ASSERT_TRUE(std::ranges::equal(pr.state().graph->neighbors(m), s.model->lattice.graph->neighbors(m))) << m;
}

TEST(PhysicsVariants, TokenRingMatchesExactlyTheStaticRing) {
  expect_same_matches_as_static("token_ring_physics.toml", "token_ring.toml", 100);
}

// Random walks of every operation on a physics scenario (steps, seeks, set, remove, push,
// watchpoints added and removed) against a straight run with the walk's interventions scheduled:
// equal hashes at every step and equal matches, on 1 and 2 threads.
TEST(PhysicsSession, RandomWalksEqualTheStraightRunWithTheSameEvents) {
  constexpr int64_t kSteps = 40;
  const std::string texts[] = {"modules(a b c); (a.isLeader = 1) and (c.isLeader = 1)",
                               "modules(a b); (a.isLeader = 1) and (b.isLeader = 0)"};
  size_t interventions = 0;
  for (unsigned threads : {1u, 2u}) {
    for (uint32_t seed = 1; seed <= 2; ++seed) {
      std::mt19937 rng(seed * 104729 + threads);
      auto pick = [&](int64_t n) { return static_cast<int64_t>(rng() % static_cast<uint64_t>(n)); };
      Scenario s = load_file("leader_election_physics.toml");
      const uint32_t modules = s.model->module_count();
      const int leader = s.model->column("isLeader");
      sim::Session run(*s.model, *s.world, {.threads = threads, .end = kSteps, .history_bytes = 2 << 20});
      std::string log;
      for (int op = 0; op < 16; ++op) {
        const int64_t kind = pick(7);
        if (kind <= 1) {
          run.run_until(std::min<int64_t>(kSteps, run.current() + 2 + pick(8)));
          log += " run>" + std::to_string(run.current());
        } else if (kind == 2 && run.latest() >= 0) {
          run.seek(pick(run.latest() + 1));
          log += " seek" + std::to_string(run.current());
        } else if (kind == 3) {
          const auto m = static_cast<sim::ModuleId>(pick(modules));
          ASSERT_EQ(run.intervene({.kind = sim::Intervention::Kind::Set, .module = m, .column = leader, .value = 1}),
                    "");
          log += " set@" + std::to_string(run.current());
        } else if (kind == 4) {
          ASSERT_EQ(run.intervene({.kind = sim::Intervention::Kind::Remove, .module = sim::ModuleId(pick(modules))}),
                    "");
          log += " remove@" + std::to_string(run.current());
        } else if (kind == 5) {
          const sim::Vec3 impulse{float(pick(40) - 20), float(pick(40) - 20), float(pick(30))};
          ASSERT_EQ(
              run.intervene(
                  {.kind = sim::Intervention::Kind::Push, .module = sim::ModuleId(pick(modules)), .impulse = impulse}),
              "");
          log += " push@" + std::to_string(run.current());
        } else {
          const size_t which = static_cast<size_t>(pick(2));
          auto compiled =
              watch::compile_watchpoint("w" + std::to_string(which), watch::SourceText("<walk>", texts[which]));
          ASSERT_TRUE(run.set_watch({std::get<watch::Watchpoint>(std::move(compiled)),
                                     pick(2) ? watch::Algorithm::Centralized : watch::Algorithm::Distributed,
                                     sim::MatchAction::Log,
                                     {}}));
          log += " watch" + std::to_string(which);
        }
      }
      while (run.current() < kSteps - 1) run.run_until(kSteps);  // through the pauses
      SCOPED_TRACE("threads " + std::to_string(threads) + ", walk" + log);

      Scenario again = load_file("leader_election_physics.toml");
      again.model->watches.clear();  // the session's, as the walk left them
      for (const sim::HostedWatchpoint& h : run.watches().hosted()) again.model->watches.push_back(h);
      sim::Session straight(*again.model, *again.world, {.threads = threads, .events = run.interventions()});
      std::vector<uint64_t> hashes;
      while (straight.current() < kSteps - 1)
        straight.run_until(kSteps, [&](const sim::State& st, const sim::StepOutput&) {
          hashes.push_back(sim::hash_state(st).whole());
        });
      EXPECT_EQ(matches_of(run), matches_of(straight));
      interventions += run.interventions().size();
      ASSERT_EQ(run.latest() + 1, kSteps);
      for (int64_t t = 0; t < kSteps; ++t) {
        ASSERT_TRUE(run.seek(t));
        ASSERT_EQ(run.hash().whole(), hashes[size_t(t)]) << "step " << t;
      }
    }
  }
  EXPECT_GE(interventions, 4u) << "the walks intervened";
}

// Every physics scenario that runs on, with its scheduled events (the plausibility scenes of
// scenarios/physics/ among them, and a surface flow with hundreds gliding at once): the same
// hash every step on 1 thread and on 2, through a seek back and on again; and every step's contact
// graph, read by comparing only what the world says changed, equals one read by comparing every
// module (a restored state is compared in full once).
TEST(PhysicsScenarios, SameHashesOnOneAndTwoThreadsThroughSeeksAndContactsReadByWhatChanged) {
  const auto check = [](const std::function<Scenario()>& load, int64_t steps, const std::string& name) {
    std::vector<uint64_t> one;
    {
      Scenario s = load();
      sim::Session run(*s.model, *s.world, {.threads = 1, .events = s.events});
      run.run_until(steps,
                    [&](const sim::State& st, const sim::StepOutput&) { one.push_back(sim::hash_state(st).whole()); });
    }
    Scenario s = load();
    auto* world = dynamic_cast<physics::BulletWorld*>(s.world.get());
    ASSERT_NE(world, nullptr) << name;
    world->check_contacts();
    sim::Session run(*s.model, *s.world, {.threads = 2, .history_bytes = 16 << 20, .events = s.events});
    size_t step = 0, differ = 0;
    EXPECT_NO_THROW(run.run_until(steps, [&](const sim::State& st, const sim::StepOutput&) {
      differ += step >= one.size() || sim::hash_state(st).whole() != one[step];
      ++step;
    })) << name;
    EXPECT_EQ(differ, 0u) << name;
    const int64_t reached = run.state().step;
    ASSERT_GT(reached, 20) << name;
    ASSERT_EQ(size_t(reached), one.size()) << name;
    for (const int64_t t : {reached / 3, reached - 1, int64_t{2}}) {
      ASSERT_TRUE(run.seek(t)) << name;
      EXPECT_EQ(run.hash().whole(), one[size_t(t)]) << name << " step " << t;
    }
    EXPECT_NO_THROW(run.run_until(reached)) << name;
    EXPECT_EQ(run.hash().whole(), one.back()) << name;
  };
  for (const char* name :
       {"push_wall.toml", "slide.toml", "smart_blocks_flow.toml", "catoms3d_roll.toml", "token_ring_physics.toml",
        "demolition.toml", "physics/column.toml", "physics/resting_boxes.toml", "physics/launched_box.toml",
        "physics/heavy_on_light.toml", "catoms2d_climb.toml", "hexanodes_walk.toml", "physics/disc_pile.toml"})
    check([&] { return load_file(name); }, 150, name);
  check([] { return load_file("physics/pile.toml"); }, 30, "physics/pile.toml");  // 1,000 free boxes: dear
  check([] { return surface_flow(20); }, 80, "surface_flow 20");
}

}  // namespace
}  // namespace dw::scenarios
