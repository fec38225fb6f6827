// A pivot's hinge (sim::Mover::hinge, physics/contact_graph.h): a cube turning about the edge it
// shares with its partner touches that partner along the edge all the turn long, so the two are
// neighbours, both ways, at every step strictly inside the turn, though GJK finds their rounded
// edges apart in the middle of it.
#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <variant>

#include "physics/bullet_world.h"
#include "physics/contact_graph.h"
#include "physics/dynamics.h"
#include "physics/pivot.h"
#include "sim/session.h"
#include "sim/state.h"
#include "tests/physics/scripted_program.h"

namespace dw::physics {
namespace {

constexpr int64_t kTurnSteps = 20;

// A cube on top of module 0 (a row of two on the ground) turning a quarter about their shared
// edge towards module 1, measured at each of the steps of its turn.
TEST(Hinge, AContactGraphListsTheHingePartnerAtEveryStepOfTheTurn) {
  sim::Bodies b;
  b.poses.resize(3);
  b.poses.set(1, {.position = {1, 0, 0}});
  b.poses.set(2, {.position = {0, 0, 1}});
  const std::vector<uint8_t> present(3, 1);
  const auto planned = pivot_arcs(ModuleShape::Box, {0, 0, 1}, {0, 0, 0}, {1, 0, 0});
  ASSERT_TRUE(std::holds_alternative<std::vector<PivotArc>>(planned));
  const PivotArc arc = std::get<std::vector<PivotArc>>(planned)[0];
  sim::Mover mover{.module = 2, .from = b.poses[2], .steps = kTurnSteps};
  mover.pivot = arc.pivot, mover.axis = arc.axis, mover.angle = arc.angle, mover.spin = arc.spin;
  sim::WorkerPool workers(1);
  for (const bool hinged : {false, true}) {
    mover.hinge = hinged ? 0 : sim::kNoHinge;
    b.movers = {mover};
    ContactGraph contacts(ModuleShape::Box, PhysicsSettings{}.contact_threshold);
    int apart = 0;
    for (int64_t k = 1; k < kTurnSteps; ++k) {
      b.poses.set(2, turn(mover, float(k) / float(kTurnSteps)));
      const std::vector<sim::ModuleId> changed{2};
      const auto graph = contacts.update(b, present, workers, k == 1 ? nullptr : &changed);
      if (hinged) {
        EXPECT_TRUE(graph->adjacent(2, 0)) << "step " << k << " of the turn";
        EXPECT_TRUE(graph->adjacent(0, 2)) << "step " << k << " of the turn: both ways";
      }
      apart += !graph->adjacent(2, 0);
    }
    if (!hinged) {
      EXPECT_GT(apart, 0) << "without the hinge the rounded edges part in the middle of the turn";
    }
  }
}

// The world's own pivot: module 3, on top of module 0, asks at step 2 to roll over the edge it
// shares with 0 into the cell on top of module 1. The graph measured from each pose strictly
// inside the turn lists 0 as 3's neighbour and 3 as 0's.
TEST(Hinge, APivotingCubeListsItsHingePartnerAtEveryStepStrictlyInsideItsTurn) {
  sim::Lattice lattice = sim::make_lattice({sim::LatticeKind::Cubic, {3, 1, 2}});
  sim::leave_empty(lattice, {1, 0, 1}, {2, 0, 1});
  const auto model = test::scripted_model(std::move(lattice), [](sim::ModuleContext& m) {
    if (m.id() == 3 && m.step() == 2) m.pivot(0, {1, 0, 0});
  });
  PhysicsSettings settings;
  settings.move_steps = kTurnSteps;
  BulletWorld world(settings, model->lattice);
  sim::Session run(*model, world, {.threads = 1});
  int inside = 0;
  for (int64_t t = 3; t <= 2 + kTurnSteps + 2; ++t) {
    run.run_until(t);
    const sim::State& s = run.state();
    if (!s.bodies.moving(3)) continue;
    ++inside;
    EXPECT_TRUE(s.graph->adjacent(3, 0)) << "at the end of step " << t - 1;
    EXPECT_TRUE(s.graph->adjacent(0, 3)) << "at the end of step " << t - 1 << ": both ways";
  }
  EXPECT_EQ(inside, kTurnSteps - 1) << "the steps strictly inside the turn";
  EXPECT_FALSE(run.state().bodies.moving(3));
  EXPECT_FALSE(run.state().graph->adjacent(3, 0)) << "arrived, diagonal to its partner";
}

}  // namespace
}  // namespace dw::physics
