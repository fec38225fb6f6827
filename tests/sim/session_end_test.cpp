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

// Two watchpoints that explode in the drain (three free slots in any shape, simultaneous states,
// whose PatternMatchers in flight go on growing after the last step) on a run of one step.
std::unique_ptr<Model> exploding_in_the_drain(size_t copies) {
  std::vector<std::unique_ptr<const HostProgram>> programs;
  programs.push_back(std::make_unique<test_programs::Gossip>());
  std::vector<HostedWatchpoint> hosted;
  for (size_t i = 0; i < copies; ++i) {
    watch::DetectorOptions options;
    options.shape = watch::GroupShape::Any;
    options.states = watch::States::Simultaneous;
    hosted.push_back(HostedWatchpoint{test_programs::compile("modules(a b c); a.v < 3 and b.v < 3 and c.v < 3"),
                                      watch::Algorithm::Distributed, MatchAction::Log, options});
    hosted.back().watchpoint.name = "w" + std::to_string(i);
  }
  return std::get<std::unique_ptr<Model>>(
      build_model(make_lattice({LatticeKind::Cubic, {4, 3, 2}}), std::move(programs), std::move(hosted), 1));
}

// The end-of-run drain is charged against the whole run's PatternMatcher budget as a step is
// (issue 62): it was charged only against each watchpoint's own. With the least budget under
// which one of the watchpoints runs to its end, drain included, a second one stops in the drain,
// in the session at its end and in `run`'s drain alike, on any thread count; the first drains.
TEST(Session, TheDrainIsChargedAgainstTheRunsBudgetAsAStepIs) {
  const auto one = exploding_in_the_drain(1), two = exploding_in_the_drain(2);
  const auto stops = [&](const Model& model, uint64_t budget, uint32_t w) {
    StaticLatticeWorld world;
    Session s(model, world, {.threads = 1, .end = 1, .run_live_budget = budget});
    s.run_until(1);
    return s.stats(w).stopped;
  };
  uint64_t low = 1, high = uint64_t{1} << 24;  // the least budget that does not stop it
  ASSERT_FALSE(stops(*one, high, 0));
  while (low < high) {
    const uint64_t mid = low + (high - low) / 2;
    (stops(*one, mid, 0) ? low = mid + 1 : high = mid);
  }
  const uint64_t budget = low;
  StaticLatticeWorld free_world;
  Session free(*two, free_world, {.threads = 1, .end = 1, .run_live_budget = 0});
  free.run_until(1);
  uint64_t at_step_0 = 0;  // what the two wanted at the one step, before the drain
  for (uint32_t w = 0; w < 2; ++w)
    for (const watch::StepStats& s : free.stats(w).steps) at_step_0 += s.live + s.messages;
  ASSERT_LE(at_step_0, budget) << "the step alone fits the budget: only the drain can pass it";
  for (const unsigned threads : {1u, 2u}) {
    for (const bool drained : {false, true}) {
      StaticLatticeWorld world;
      Session s(*two, world, {.threads = threads, .end = 1, .run_live_budget = budget});
      s.run_until(1);
      if (drained) s.drain();  // what `dwatch run` does at the end
      EXPECT_FALSE(s.stats(0).stopped) << s.stats(0).stop_reason;
      EXPECT_EQ(s.match_count(0), free.match_count(0)) << "the first drains whole";
      ASSERT_TRUE(s.stats(1).stopped) << "threads " << threads << (drained ? ", drained" : "");
      EXPECT_NE(s.stats(1).stop_reason.find("budget of " + std::to_string(budget) +
                                            " live PatternMatchers in the drain after step 0"),
                std::string::npos)
          << s.stats(1).stop_reason;
      EXPECT_EQ(s.match_count(1), 0u) << "the drain that passed the budget reports nothing";
      EXPECT_GT(free.match_count(1), 0u);
    }
  }
}

}  // namespace
}  // namespace dw::sim
