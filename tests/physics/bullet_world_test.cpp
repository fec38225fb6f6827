// The Bullet World (physics/bullet_world.cpp): a resting lattice keeps exactly its face contacts,
// hex and ring layouts touch as their lattices say, modules pushed apart lose their edge when the
// gap passes the threshold (and a watchpoint stops matching at that step), lattice moves arrive
// exactly and latch, and a world without bodies refuses actuation.
#include "physics/bullet_world.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "physics/clusters.h"
#include "physics/dynamics.h"
#include "sim/session.h"
#include "sim/state.h"
#include "watch/watchpoint.h"

namespace dw::physics {
namespace {

// A program that runs a test's lambda on every module.
class Scripted final : public sim::HostProgram {
 public:
  explicit Scripted(std::function<void(sim::ModuleContext&)> f) : f_(std::move(f)) {}
  std::string_view name() const override { return "scripted"; }
  std::vector<sim::VariableSpec> variables() const override { return {{"side", 0}}; }
  void step(sim::ModuleContext& m) const override {
    m.set(0, m.id());
    f_(m);
  }

 private:
  std::function<void(sim::ModuleContext&)> f_;
};

std::unique_ptr<sim::Model> model_of(
    sim::Lattice lattice, std::function<void(sim::ModuleContext&)> f = [](auto&) {},
    std::vector<std::string> watches = {}) {
  std::vector<std::unique_ptr<const sim::HostProgram>> programs;
  programs.push_back(std::make_unique<Scripted>(std::move(f)));
  std::vector<sim::HostedWatchpoint> hosted;
  for (const std::string& text : watches) {
    auto w = watch::compile_watchpoint("w", watch::SourceText("<test>", text));
    hosted.push_back(
        {std::get<watch::Watchpoint>(std::move(w)), watch::Algorithm::Centralized, sim::MatchAction::Log, {}});
  }
  auto built = sim::build_model(std::move(lattice), std::move(programs), std::move(hosted), 1);
  return std::move(std::get<std::unique_ptr<sim::Model>>(built));
}

std::vector<std::pair<sim::ModuleId, sim::ModuleId>> edges(const sim::NeighborGraph& g) {
  std::vector<std::pair<sim::ModuleId, sim::ModuleId>> out;
  for (sim::ModuleId m = 0; m < g.module_count(); ++m)
    for (sim::ModuleId o : g.neighbors(m))
      if (m < o) out.emplace_back(m, o);
  return out;
}

float gap_x(const sim::State& s, sim::ModuleId a, sim::ModuleId b) {
  return std::abs(s.bodies.poses[b].position[0] - s.bodies.poses[a].position[0]) - 1;
}

void expect_cube_holds(PhysicsSettings settings, uint32_t n, size_t face_pairs) {
  const auto model = model_of(sim::make_lattice({sim::LatticeKind::Cubic, {n, n, n}}));
  BulletWorld world(settings, model->lattice);
  sim::Session run(*model, world, {.threads = 1});
  const auto lattice_edges = edges(*model->lattice.graph);
  ASSERT_EQ(lattice_edges.size(), face_pairs);
  EXPECT_EQ(edges(*run.state().graph), lattice_edges) << "step 0: exactly the face pairs, no diagonals";
  run.run_until(600);
  EXPECT_EQ(edges(*run.state().graph), lattice_edges) << "after 600 steps";
  float drift = 0;
  for (sim::ModuleId m = 0; m < model->module_count(); ++m)
    for (int i = 0; i < 3; ++i)
      drift = std::max(drift, std::abs(run.state().bodies.poses[m].position[i] - model->lattice.position(m)[i]));
  EXPECT_LT(drift, 0.02f);
}

TEST(BulletWorld, AnchoredCubeKeepsExactlyItsFaceContactsFor600Steps) { expect_cube_holds({}, 10, 2700); }

// A latched lattice's bonds are its neighbours' pairs and its bottom layer's to the ground, and
// the set keeps them as its default: only the bottom layer's bytes take memory, a twentieth of
// what a sorted list of them took.
TEST(BulletWorld, ALatchedLatticesBondsAreItsPairsKeptAsTheDefault) {
  for (const sim::LatticeSpec& spec :
       {sim::LatticeSpec{sim::LatticeKind::Cubic, {12, 12, 12}}, sim::LatticeSpec{sim::LatticeKind::Fcc, {8, 8, 8}}}) {
    const auto model = model_of(sim::make_lattice(spec));
    BulletWorld world({}, model->lattice);
    sim::Session run(*model, world, {.threads = 1});
    std::vector<sim::Bond> expected, bonds;
    sim::for_lattice_pairs(spec, {}, [&](sim::ModuleId a, sim::ModuleId b) { expected.push_back({a, b}); });
    for (sim::ModuleId m = 0; m < spec.size[0] * spec.size[1]; ++m) expected.push_back({m, sim::kGround});
    std::sort(expected.begin(), expected.end());
    run.state().bodies.bonds.for_each([&](const sim::Bond& x) { bonds.push_back(x); });
    EXPECT_EQ(bonds, expected);
    EXPECT_TRUE(run.state().bodies.bonds.listed().empty());
    EXPECT_LT(20 * run.state().bodies.bonds.bytes(), expected.size() * sizeof(sim::Bond));
  }
}

TEST(BulletWorld, FreeCubeRestingOnTheGroundKeepsItsFaceContacts) {
  PhysicsSettings s;
  s.anchor = false;  // one rigid cluster, a dynamic body standing on the ground
  expect_cube_holds(s, 6, 540);
}

TEST(BulletWorld, LooseModulesWithoutBondsStillTouchAtTheStart) {
  PhysicsSettings s;
  s.bonds = false;
  s.anchor = false;
  const auto model = model_of(sim::make_lattice({sim::LatticeKind::Cubic, {4, 4, 4}}));
  BulletWorld world(s, model->lattice);
  sim::Session run(*model, world, {.threads = 1});
  EXPECT_EQ(edges(*run.state().graph), edges(*model->lattice.graph));
  EXPECT_TRUE(run.state().bodies.bonds.empty());
  EXPECT_EQ(run.state().bodies.clusters.size(), 64u);
}

TEST(BulletWorld, HexAndRingInteriorsHaveSixAndTwoNeighbours) {
  const auto hex = model_of(sim::make_lattice({sim::LatticeKind::Hex2d, {8, 8, 1}}));
  BulletWorld hex_world({}, hex->lattice);
  EXPECT_EQ(hex_world.shape(), ModuleShape::Cylinder);
  sim::Session hex_run(*hex, hex_world, {.threads = 1});
  hex_run.run_until(30);
  const sim::NeighborGraph& g = *hex_run.state().graph;
  for (uint32_t y = 1; y + 1 < 8; ++y)
    for (uint32_t x = 1; x + 1 < 8; ++x) EXPECT_EQ(g.neighbors(x + 8 * y).size(), 6u) << x << "," << y;
  EXPECT_EQ(edges(g), edges(*hex->lattice.graph));

  const auto ring = model_of(sim::make_lattice({sim::LatticeKind::Ring, {12, 1, 1}}));
  BulletWorld ring_world({}, ring->lattice);
  EXPECT_EQ(ring_world.shape(), ModuleShape::Sphere);
  sim::Session ring_run(*ring, ring_world, {.threads = 1});
  ring_run.run_until(30);
  for (sim::ModuleId m = 0; m < 12; ++m) EXPECT_EQ(ring_run.state().graph->neighbors(m).size(), 2u);
  EXPECT_EQ(edges(*ring_run.state().graph), edges(*ring->lattice.graph));
}

// Catoms 3D: spheres on the FCC lattice touch exactly their 12 lattice neighbours, latched and
// resting, and free on the ground after it settled.
TEST(BulletWorld, FccSpheresTouchExactlyTheLatticesNeighbours) {
  for (const bool anchored : {true, false}) {
    PhysicsSettings s;
    s.anchor = anchored;
    const auto fcc = model_of(sim::make_lattice({sim::LatticeKind::Fcc, {5, 5, 4}}));
    BulletWorld world(s, fcc->lattice);
    EXPECT_EQ(world.shape(), ModuleShape::Sphere);
    sim::Session run(*fcc, world, {.threads = 1});
    EXPECT_EQ(edges(*run.state().graph), edges(*fcc->lattice.graph)) << "at the start, anchored " << anchored;
    run.run_until(60);
    const sim::NeighborGraph& g = *run.state().graph;
    EXPECT_EQ(edges(g), edges(*fcc->lattice.graph)) << "after 60 steps, anchored " << anchored;
    uint32_t twelve = 0;
    for (sim::ModuleId m = 0; m < g.module_count(); ++m) twelve += g.neighbors(m).size() == 12;
    EXPECT_EQ(twelve, 3u * 3u * 2u);  // x, y in 1..3 on the two inner layers
  }
}

TEST(BulletWorld, ModulesPushedApartLoseTheirEdgeWhenTheGapPassesTheThreshold) {
  PhysicsSettings s;
  s.bonds = false;
  s.anchor = false;
  s.gravity = {0, 0, 0};  // no friction with the ground: they glide apart at constant speed
  const auto model = model_of(sim::make_lattice({sim::LatticeKind::Cubic, {2, 1, 1}}),
                              [](sim::ModuleContext& m) {
                                if (m.step() == 5) m.push({m.id() == 0 ? -0.03f : 0.03f, 0, 0});  // 0.03 m/s each way
                              },
                              {"modules(a b); (a.side = 0) and (b.side = 1)"});
  BulletWorld world(s, model->lattice);
  sim::Session run(*model, world, {.threads = 1});
  std::vector<float> gaps;
  std::vector<bool> adjacent;
  run.run_until(40, [&](const sim::State& st, const sim::StepOutput& out) {
    gaps.push_back(gap_x(st, 0, 1));
    adjacent.push_back(out.graph->adjacent(0, 1));
  });
  // The graph of step t comes from the poses after step t - 1.
  int64_t lost = -1;
  for (size_t t = 1; t < gaps.size(); ++t) {
    EXPECT_EQ(adjacent[t], gaps[t - 1] <= s.contact_threshold) << "step " << t << " gap " << gaps[t - 1];
    if (lost < 0 && !adjacent[t]) lost = int64_t(t);
  }
  ASSERT_GT(lost, 7) << "the gap grows 1 mm a step: a few steps pass before it is 10 mm";
  ASSERT_LT(lost, 30);
  const sim::MatchList& matches = run.matches(0);
  ASSERT_FALSE(matches.t.empty());
  EXPECT_EQ(matches.t.back() + 1, lost) << "the watchpoint matches until the edge is lost";
  EXPECT_EQ(int64_t(matches.size()), lost) << "and at every step before";
}

TEST(BulletWorld, LatticeMoveGlidesIntoTheFreeCellAndLatches) {
  sim::Lattice lattice = sim::make_lattice({sim::LatticeKind::Cubic, {3, 1, 2}});
  sim::leave_empty(lattice, {1, 0, 1}, {2, 0, 1});  // the top row is free but for module 3
  PhysicsSettings s;
  s.move_steps = 10;
  const auto model = model_of(lattice, [](sim::ModuleContext& m) {
    if (m.id() == 3 && m.step() == 2) m.move({1, 0, 0});
  });
  BulletWorld world(s, model->lattice);
  sim::Session run(*model, world, {.threads = 1});
  EXPECT_TRUE(run.state().graph->adjacent(3, 0));
  run.run_until(3);  // asked at step 2: a tenth of the way at step 3, there at step 12
  EXPECT_TRUE(run.state().bodies.moving(3));
  EXPECT_EQ(run.state().bodies.cluster_of[3], sim::kNoCluster);
  EXPECT_FALSE(run.state().bodies.bonds.contains(sim::Bond{0, 3}));
  EXPECT_FLOAT_EQ(run.state().bodies.poses[3].position[0], 0.1f);
  EXPECT_TRUE(run.state().graph->adjacent(3, 0)) << "sliding over module 0, still touching it";
  EXPECT_TRUE(run.state().graph->adjacent(3, 1)) << "and now module 1 too";
  run.run_until(11);
  EXPECT_TRUE(run.state().bodies.moving(3));
  run.run_until(12);
  EXPECT_FALSE(run.state().bodies.moving(3));
  EXPECT_FALSE(run.state().graph->adjacent(3, 0)) << "it left module 0 behind";
  const sim::Pose& p = run.state().bodies.poses[3];
  EXPECT_EQ(p.position, (sim::Vec3{1, 0, 1})) << "exactly in the cell";
  EXPECT_TRUE(run.state().graph->adjacent(3, 1)) << "on top of module 1";
  EXPECT_TRUE(run.state().bodies.bonds.contains(sim::Bond{1, 3}));
  EXPECT_EQ(run.state().bodies.cluster_of[3], run.state().bodies.cluster_of[1]) << "latched into the anchored row";
}

TEST(BulletWorld, MoveIntoATakenCellIsRefused) {
  const auto model = model_of(sim::make_lattice({sim::LatticeKind::Cubic, {2, 1, 1}}), [](sim::ModuleContext& m) {
    if (m.id() == 0 && m.step() == 1) m.move({1, 0, 0});
  });
  BulletWorld world({}, model->lattice);
  sim::Session run(*model, world, {.threads = 1});
  run.run_until(5);
  EXPECT_TRUE(run.state().bodies.movers.empty());
  EXPECT_EQ(run.state().bodies.poses[0].position, (sim::Vec3{0, 0, 0}));
}

// Pivots (physics/pivot.h). A cube on top of module 0 rolls about their shared edge into the
// next cell along the row: lifted over the edge halfway, exactly in the cell at the end, turned a
// quarter about y, latched to module 1 below it and no longer touching module 0.
TEST(BulletWorld, CubeRollsAboutTheEdgeItSharesIntoTheNextCell) {
  sim::Lattice lattice = sim::make_lattice({sim::LatticeKind::Cubic, {3, 1, 2}});
  sim::leave_empty(lattice, {1, 0, 1}, {2, 0, 1});
  PhysicsSettings s;
  s.move_steps = 10;
  const auto model = model_of(lattice, [](sim::ModuleContext& m) {
    if (m.id() == 3 && m.step() == 2) m.pivot(0, {1, 0, 0});
  });
  BulletWorld world(s, model->lattice);
  sim::Session run(*model, world, {.threads = 1});
  run.run_until(7);  // asked at step 2: half way at step 7
  EXPECT_TRUE(run.state().bodies.moving(3));
  EXPECT_NEAR(run.state().bodies.poses[3].position[0], 0.5f, 1e-5f);
  EXPECT_NEAR(run.state().bodies.poses[3].position[2], 0.5f + std::sqrt(0.5f), 1e-5f) << "over the edge";
  run.run_until(13);
  const sim::State& st = run.state();
  EXPECT_FALSE(st.bodies.moving(3));
  EXPECT_EQ(st.bodies.poses[3].position, (sim::Vec3{1, 0, 1}));
  const auto& q = st.bodies.poses[3].orientation;
  EXPECT_NEAR(q[1], std::sqrt(0.5f), 1e-5f);
  EXPECT_NEAR(q[3], std::sqrt(0.5f), 1e-5f);
  EXPECT_EQ(st.graph->neighbors(3).size(), 1u);
  EXPECT_TRUE(st.graph->adjacent(3, 1));
  EXPECT_TRUE(st.bodies.bonds.contains(sim::Bond{1, 3}));
}

// A cube on top of a lone module goes over its edge, half a turn, onto the ground beside it.
TEST(BulletWorld, CubeGoesOverTheEdgeOntoTheNextFace) {
  sim::Lattice lattice = sim::make_lattice({sim::LatticeKind::Cubic, {2, 1, 2}});
  sim::leave_empty(lattice, {1, 0, 0}, {1, 0, 1});
  PhysicsSettings s;
  s.move_steps = 12;
  const auto model = model_of(lattice, [](sim::ModuleContext& m) {
    if (m.id() == 2 && m.step() == 1) m.pivot(0, {1, 0, -1});
  });
  BulletWorld world(s, model->lattice);
  sim::Session run(*model, world, {.threads = 1});
  run.run_until(14);
  const sim::State& st = run.state();
  EXPECT_FALSE(st.bodies.moving(2));
  EXPECT_EQ(st.bodies.poses[2].position, (sim::Vec3{1, 0, 0}));
  EXPECT_TRUE(st.graph->adjacent(2, 0)) << "beside it now";
  EXPECT_TRUE(st.bodies.bonds.contains(sim::Bond{2, sim::kGround}));
}

std::string pivot_error(sim::Lattice lattice, sim::ModuleId mover, sim::ModuleId about, sim::Vec3 offset) {
  const auto model = model_of(std::move(lattice), [=](sim::ModuleContext& m) {
    if (m.id() == mover && m.step() == 1) m.pivot(about, offset);
  });
  BulletWorld world({}, model->lattice);
  sim::Session run(*model, world, {.threads = 1});
  try {
    run.run_until(5);
  } catch (const sim::ProgramError& e) {
    return e.what();
  }
  return "";
}

// A taken cell, a sweep through another module, a non-neighbour, or a cell no pivot about that
// neighbour reaches: each a program error that says which.
TEST(BulletWorld, APivotThatCannotHappenIsAProgramErrorSayingWhy) {
  const auto has = [](const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
  };
  // 2x1x2 full: the cell at (1, 0, 1) holds module 3.
  std::string e = pivot_error(sim::make_lattice({sim::LatticeKind::Cubic, {2, 1, 2}}), 2, 0, {1, 0, 0});
  EXPECT_TRUE(has(e,
                  "a pivot of module 2 at step 1 about module 0 to the cell at (1, 0, 0) from it: the cell is "
                  "taken by module 3"))
      << e;
  // A module on top of the roller: its corner would pass through it.
  sim::Lattice stacked = sim::make_lattice({sim::LatticeKind::Cubic, {2, 1, 3}});
  sim::leave_empty(stacked, {1, 0, 1}, {1, 0, 2});
  e = pivot_error(stacked, 2, 0, {1, 0, 0});
  EXPECT_TRUE(has(e, "its sweep passes through module 4")) << e;
  // Module 0 of a 3-row is no neighbour of module 2.
  e = pivot_error(sim::make_lattice({sim::LatticeKind::Cubic, {3, 1, 1}}), 2, 0, {0, 1, 0});
  EXPECT_TRUE(has(e, "asked to pivot about module 0 at step 1, which is not its neighbour")) << e;
  // Along the way to the neighbour: no pivot goes there.
  e = pivot_error(sim::make_lattice({sim::LatticeKind::Cubic, {3, 1, 1}}), 2, 1, {-1, 0, 0});
  EXPECT_TRUE(has(e, "a cube pivots about a neighbour by one cell along its face")) << e;
}

// A catom on the fcc lattice rolls over a neighbour into a cell touching both; it lands exactly
// in the lattice's cell, touching the four catoms under that cell.
TEST(BulletWorld, CatomRollsOverANeighbourIntoTheNextFccCell) {
  sim::Lattice lattice = sim::make_lattice({sim::LatticeKind::Fcc, {3, 3, 2}});
  sim::leave_empty(lattice, {1, 0, 1}, {2, 2, 1});
  sim::leave_empty(lattice, {0, 1, 1}, {0, 2, 1});  // the top layer holds site (0, 0) only: module 9
  PhysicsSettings s;
  s.move_steps = 10;
  const auto model = model_of(lattice, [](sim::ModuleContext& m) {
    if (m.id() == 9 && m.step() == 1) m.pivot(1, {1, 0, 0});
  });
  BulletWorld world(s, model->lattice);
  sim::Session run(*model, world, {.threads = 1});
  EXPECT_EQ(run.state().graph->neighbors(9).size(), 4u);
  run.run_until(6);
  EXPECT_TRUE(run.state().graph->adjacent(9, 1)) << "rolling on module 1";
  run.run_until(12);
  const sim::State& st = run.state();
  EXPECT_FALSE(st.bodies.moving(9));
  EXPECT_EQ(st.bodies.poses[9].position, model->lattice.position(10));
  const std::vector<sim::ModuleId> under{1, 2, 4, 5};
  EXPECT_EQ(std::vector<sim::ModuleId>(st.graph->neighbors(9).begin(), st.graph->neighbors(9).end()), under);
}

// Catoms 2D: a cylinder of a hex layer rolls over a neighbour into the empty cell beside both
// (the cell across from that neighbour left empty too, or the sweep would pass through it), and
// touches exactly the modules one cell from its new place.
TEST(BulletWorld, CylinderRollsOverANeighbourIntoTheHexCellBesideBoth) {
  sim::Lattice lattice = sim::make_lattice({sim::LatticeKind::Hex2d, {5, 5, 1}});
  sim::leave_empty(lattice, {2, 2, 0}, {2, 2, 0});  // the cell it rolls into
  sim::leave_empty(lattice, {1, 3, 0}, {1, 3, 0});  // across from module 6, the one it rolls over
  PhysicsSettings s;
  s.move_steps = 10;
  const auto model = model_of(lattice, [](sim::ModuleContext& m) {
    if (m.id() == 11 && m.step() == 1) m.pivot(6, {1, 0, 0});  // (1, 2) over (1, 1) into (2, 2)
  });
  BulletWorld world(s, model->lattice);
  EXPECT_EQ(world.shape(), ModuleShape::Cylinder);
  sim::Session run(*model, world, {.threads = 1});
  run.run_until(12);
  const sim::State& st = run.state();
  const sim::Vec3& at = model->lattice.position(12);
  EXPECT_LT(std::hypot(st.bodies.poses[11].position[0] - at[0], st.bodies.poses[11].position[1] - at[1]), 1e-5f);
  std::vector<sim::ModuleId> expected;
  for (sim::ModuleId o = 0; o < model->module_count(); ++o) {
    const sim::Vec3& p = st.bodies.poses[o].position;
    if (o != 11 && st.present[o] && std::abs(std::hypot(p[0] - at[0], p[1] - at[1]) - 1) < 1e-3f) expected.push_back(o);
  }
  EXPECT_EQ(expected, (std::vector<sim::ModuleId>{6, 7, 13, 17}));
  EXPECT_EQ(std::vector<sim::ModuleId>(st.graph->neighbors(11).begin(), st.graph->neighbors(11).end()), expected);
}

// Pivots on 1 and 2 threads give the same hash every step, and a run seeked back and forth
// through them equals the run that went straight.
TEST(BulletWorld, PivotsAreDeterministicOnAnyThreadCountAndThroughSeeks) {
  sim::Lattice lattice = sim::make_lattice({sim::LatticeKind::Cubic, {6, 2, 2}});
  sim::leave_empty(lattice, {1, 0, 1}, {5, 1, 1});  // two rollers on top at x = 0: modules 12 and 18
  PhysicsSettings s;
  s.move_steps = 7;
  const auto program = [](sim::ModuleContext& m) {
    // Each top module rolls along +x every ten steps about the module under it (the bottom layer
    // never moves: its ids are its cells').
    const sim::Vec3& at = m.pose().position;
    if (at[2] < 0.5f || m.moving() || m.step() % 10 != 1 || at[0] > 4.5f) return;
    const auto below = static_cast<sim::ModuleId>(std::lround(at[0]) + 6 * std::lround(at[1]));
    if (m.is_neighbor(below)) m.pivot(below, {1, 0, 0});
  };
  const auto hashes = [&](unsigned threads) {
    const auto model = model_of(lattice, program);
    BulletWorld world(s, model->lattice);
    sim::Session run(*model, world, {.threads = threads});
    std::vector<uint64_t> h;
    run.run_until(60, [&](const sim::State& st, const sim::StepOutput&) { h.push_back(sim::hash_state(st).whole()); });
    return h;
  };
  const std::vector<uint64_t> one = hashes(1);
  EXPECT_EQ(hashes(2), one);
  const auto model = model_of(lattice, program);
  BulletWorld world(s, model->lattice);
  sim::Session run(*model, world, {.threads = 2, .history_bytes = 4 << 20});
  run.run_until(60);
  EXPECT_NE(run.state().bodies.poses[12].position[0], 0.0f) << "the rollers moved";
  for (int64_t t : {30, 59, 4, 15, 16, 0, 44}) {
    ASSERT_TRUE(run.seek(t));
    ASSERT_EQ(run.hash().whole(), one[size_t(t)]) << "step " << t;
  }
  // Back to the step whose pivots are carried out next, and on again: the world finds the cells
  // as they were then, not as it last saw them.
  ASSERT_TRUE(run.seek(1));
  run.run_until(60);
  EXPECT_EQ(run.hash().whole(), one[59]);
}

TEST(BulletWorld, ReleasedModuleFallsFromTheTopOfAColumn) {
  // The top of a latched column of three releases its bonds and pushes itself sideways: it slides
  // off and falls to the ground, and the column stays where it was.
  PhysicsSettings s;
  const auto model = model_of(sim::make_lattice({sim::LatticeKind::Cubic, {1, 1, 3}}), [](sim::ModuleContext& m) {
    if (m.id() == 2 && m.step() == 1) {
      m.release_all();
      m.push({4, 0, 0});
    }
  });
  BulletWorld world(s, model->lattice);
  sim::Session run(*model, world, {.threads = 1});
  run.run_until(240);
  const sim::State& st = run.state();
  EXPECT_LT(st.bodies.poses[2].position[2], 0.1f) << "it fell to the ground";
  EXPECT_GT(st.bodies.poses[2].position[0], 0.9f);
  EXPECT_FALSE(st.graph->adjacent(1, 2));
  EXPECT_EQ(st.bodies.poses[0].position, (sim::Vec3{0, 0, 0})) << "the anchored column did not move";
}

// Bonds released and made by requests (some undone within the step), a module setting off and
// arriving, the block split and joined: every step the clusters regrouped by what changed are
// those formed from all the bonds, and the contact graph read by what changed is the full one.
TEST(BulletWorld, RequestsOnBondsRegroupAsFromAllTheBonds) {
  PhysicsSettings s;
  s.move_steps = 3;
  // A 4x2x2 block latched to the ground; ids x + 4 (y + 2 z).
  const auto model = model_of(sim::make_lattice({sim::LatticeKind::Cubic, {4, 2, 2}}), [](sim::ModuleContext& m) {
    const int64_t t = m.step();
    if (t == 1 && m.id() == 13) m.release_all();    // a top corner lets go: a piece of one
    if (t == 2 && m.id() == 13) m.bond(12);         // and latches back
    if (t == 3 && m.id() == 14) m.move({0, 0, 1});  // a top module climbs onto the block
    if (t == 4 && (m.id() == 9 || m.id() == 13)) {  // the top layer's column x = 1 cut loose
      m.release_all();
    }
    if (t == 4 && m.id() == 10) m.bond(9);  // and one bond of it made again at once
    if (t == 8 && m.id() == 13) m.bond(12);
  });
  BulletWorld world(s, model->lattice);
  world.check_contacts();
  Dynamics shapes(s, ModuleShape::Box, world.ground_z());
  sim::Session run(*model, world, {.threads = 2});
  size_t most_clusters = 0;
  EXPECT_NO_THROW(run.run_until(16, [&](const sim::State& st, const sim::StepOutput&) {
    sim::Bodies whole = st.bodies;
    form_clusters(whole, st.present, shapes.module_shape());
    // How long a cluster has been still is the dynamics' count (Cluster::still), which clusters
    // formed afresh start at 0: the rest must be the same to the bit.
    std::vector<sim::Cluster> regrouped = st.bodies.clusters;
    for (sim::Cluster& c : regrouped) c.still = 0;
    EXPECT_EQ(whole.clusters, regrouped) << "step " << st.step;
    EXPECT_EQ(whole.members, st.bodies.members) << "step " << st.step;
    EXPECT_EQ(whole.cluster_of, st.bodies.cluster_of) << "step " << st.step;
    most_clusters = std::max(most_clusters, st.bodies.clusters.size());
  }));
  EXPECT_GE(most_clusters, 2u) << "the block was split on the way";
}

TEST(BulletWorld, ActuationWithoutBodiesIsAProgramError) {
  const auto model = model_of(sim::make_lattice({sim::LatticeKind::Cubic, {2, 1, 1}}), [](sim::ModuleContext& m) {
    if (m.step() == 3) m.push({1, 0, 0});
  });
  sim::StaticLatticeWorld world;
  sim::Session run(*model, world, {.threads = 1});
  EXPECT_THROW(run.run_until(10), sim::ProgramError);
}

TEST(BulletWorld, AMoveMustBeOneModuleLong) {
  const auto model = model_of(sim::make_lattice({sim::LatticeKind::Cubic, {2, 1, 1}}), [](sim::ModuleContext& m) {
    if (m.step() == 1 && m.id() == 1) m.move({2, 0, 0});
  });
  BulletWorld world({}, model->lattice);
  sim::Session run(*model, world, {.threads = 1});
  try {
    run.run_until(5);
    FAIL() << "a move of two cells was carried out";
  } catch (const sim::ProgramError& e) {
    EXPECT_NE(std::string(e.what()).find("module 1 at step 1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dw::physics
