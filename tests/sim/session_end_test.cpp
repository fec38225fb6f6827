// The session at the scenario's end (docs/design.md §4c, "Run's end"): it has decided every step,
// as `run` and `replay` have, and can still simulate on past the end.
#include <gtest/gtest.h>

#include "sim/session.h"
#include "sim/world.h"
#include "tests/sim/run_trail.h"
#include "tests/sim/test_programs.h"

namespace dw::sim {
namespace {

using test_programs::gossip_model;

// At the scenario's end the session has decided every step, as `run` does (design §4c, "Run's
// end"): run to the end, it holds what the drain of `run` finds (the last steps' matches of a
// watchpoint reading its neighbours a hop away, or a step ahead), and pauses on none of them;
// simulated on past the end, it forgets them and decides those steps itself, as a session that
// never stopped at the end.
TEST(Session, AtTheScenariosEndItHasDecidedWhatRunDecides) {
  const std::vector<std::pair<std::string, watch::Algorithm>> watches{
      {"modules(b); b.v = 0 and count(n in neighbors(b): n.v = 1) >= 2", watch::Algorithm::Distributed},
      {"modules(a b); (a.v = 3) and (b.next.v = 3) and (a.last.v = 0)", watch::Algorithm::Distributed}};
  const auto model = gossip_model({LatticeKind::Cubic, {5, 4, 3}}, watches);
  constexpr int64_t kEnd = 30;
  StaticLatticeWorld ended_world, drained_world, on_world;
  Session ended(*model, ended_world, {.threads = 1, .end = kEnd});
  Session drained(*model, drained_world, {.threads = 2, .end = kEnd});
  ended.run_until(kEnd);
  drained.run_until(kEnd);
  drained.drain();  // what `dwatch run` does at the end
  EXPECT_EQ(ended.decided(), kEnd - 1);
  EXPECT_EQ(test::flat_matches(ended), test::flat_matches(drained));
  ASSERT_GT(ended.matches(0).size(), 0u);
  EXPECT_EQ(ended.matches(0).t.back(), kEnd - 1) << "the last step's matches, which only a drain decides";
  for (uint32_t w = 0; w < watches.size(); ++w) EXPECT_EQ(ended.match_count(w), drained.match_count(w)) << w;
  // A pause on the same watchpoint pauses at none of the drain's matches, going over them again.
  ended.set_action(0, MatchAction::Pause);
  const MatchList& list = ended.matches(0);
  ASSERT_GT(list.size(), 0u);
  const int64_t last = list.t.back();
  ASSERT_TRUE(ended.seek(last - 1));
  const auto pause = ended.run_until(kEnd);
  EXPECT_TRUE(!pause || pause->t < last || list.detected[list.at(pause->t).first] < kEnd - 1);
  ended.set_action(0, MatchAction::Log);
  // Past the end: as a session that went on without stopping there.
  Session on(*model, on_world, {.threads = 1, .end = kEnd});
  on.decide(kEnd + 4);
  ended.decide(kEnd + 4);
  EXPECT_EQ(test::flat_matches(ended), test::flat_matches(on));
  EXPECT_EQ(ended.decided(), on.decided());
}

}  // namespace
}  // namespace dw::sim
