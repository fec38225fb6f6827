// A branch started at the current step (docs/design.md §7): the session decides that step again
// before the cursor stands on it, so what the cursor paused on stays, the step itself unchanged.
#include <gtest/gtest.h>

#include "sim/session.h"
#include "sim/world.h"
#include "tests/sim/run_trail.h"
#include "tests/sim/test_programs.h"

namespace dw::sim {
namespace {

using test_programs::gossip_model;

// Two leaders found a step late (lag 1), the other watchpoint two steps late: paused on step t, a
// `set` at t (which changes t + 1 on) keeps t's matches, t decided, as a run with the set
// scheduled finds them; without the look ahead the branch held none of them until run on.
TEST(Session, AnInterventionKeepsTheMatchPausedOn) {
  auto model = gossip_model({LatticeKind::Square2d, {5, 5, 1}},
                            {{"modules(a b); (a.v = 1) and (b.v = 1)", watch::Algorithm::Distributed},
                             {"modules(a b c); (a.v = 2) and (b.v = 2) and (c.v = 2)", watch::Algorithm::Distributed}});
  model->watches[0].action = MatchAction::Pause;
  StaticLatticeWorld world;
  Session run(*model, world, {.threads = 1, .end = 50});
  const auto pause = run.run_until(50);
  ASSERT_TRUE(pause);
  const int64_t t = pause->t;
  const auto [first, last] = run.matches(0).at(t);
  ASSERT_GT(last, first);
  const int64_t paused_on = int64_t(last - first);

  ASSERT_EQ(run.intervene({.kind = Intervention::Kind::Set, .module = 12, .column = model->column("v"), .value = 7}),
            "");
  EXPECT_EQ(run.current(), t);
  EXPECT_EQ(run.latest(), t + 2) << "ahead until every watchpoint decided step t again";
  EXPECT_GE(run.decided(), t);
  const auto [first_after, last_after] = run.matches(0).at(t);
  EXPECT_EQ(int64_t(last_after - first_after), paused_on) << "the match paused on is still there";

  // The same steps as a straight run with the set scheduled at t + 1.
  StaticLatticeWorld straight_world;
  Session straight(*model, straight_world, {.threads = 2, .end = 50, .events = run.interventions()});
  straight.run_until(t + 1);
  straight.decide(t);
  for (int64_t s = 0; s <= run.latest(); ++s) {
    ASSERT_TRUE(run.seek(s));
    ASSERT_TRUE(straight.seek(s));
    EXPECT_EQ(run.hash().whole(), straight.hash().whole()) << "step " << s;
  }
  for (uint32_t w = 0; w < 2; ++w) {
    const auto [a0, a1] = run.matches(w).at(t);
    const auto [b0, b1] = straight.matches(w).at(t);
    EXPECT_EQ(a1 - a0, b1 - b0) << "watch " << w;
  }
}

// Near the scenario's end the look ahead stops at its last step, as `run`'s does; a reloaded
// program decides the step again too.
TEST(Session, AnInterventionLooksAheadNoFurtherThanTheEnd) {
  const auto model =
      gossip_model({LatticeKind::Cubic, {4, 3, 3}},
                   {{"modules(a b c); (a.v = 1) and (b.v = 2) and (c.mix > b.mix)", watch::Algorithm::Distributed}});
  StaticLatticeWorld world;
  constexpr int64_t kEnd = 20;
  Session run(*model, world, {.threads = 1, .end = kEnd});
  run.run_until(kEnd);
  ASSERT_TRUE(run.seek(kEnd - 2));
  ASSERT_EQ(run.intervene({.kind = Intervention::Kind::Remove, .module = 5}), "");
  EXPECT_EQ(run.latest(), kEnd - 1) << "not past the end";
  EXPECT_EQ(run.current(), kEnd - 2);
  ASSERT_TRUE(run.seek(3));
  ASSERT_EQ(run.intervene({.kind = Intervention::Kind::Remove, .module = 6}), "");
  EXPECT_EQ(run.latest(), 5) << "lag 2: step 3 decided at step 5";
  EXPECT_GE(run.decided(), 3);
}

}  // namespace
}  // namespace dw::sim
