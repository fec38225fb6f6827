#include "watch/distributed_detector.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "test_ensemble.h"

namespace dw::watch {
namespace {

using testing::compile_or_die;
using testing::Match;
using testing::TestEnsemble;

// A ring of n modules, `steps` steps, x given by a function.
template <class F>
TestEnsemble ring(uint32_t n, int steps, F x) {
  TestEnsemble e(n, {"x"});
  for (int t = 0; t < steps; ++t)
    for (uint32_t m = 0; m < n; ++m) e.set(t, m, {{"x", x(t, m)}}, {(m + n - 1) % n, (m + 1) % n});
  return e;
}

TEST(DistributedDetector, SlotIFillsAtStepT0PlusIMinusOne) {
  // x = t everywhere: a match needs a to see 0 at its step and b to see 1 at its own.
  const auto e = ring(4, 3, [](int t, uint32_t) { return t; });
  const Watchpoint w = compile_or_die("modules(a b); (a.x = 0) and (b.x = 1)");
  const auto matches = e.run(Algorithm::Distributed, w);
  EXPECT_EQ(matches.size(), 8u);  // every directed edge, t0 = 0
  for (const Match& m : matches) EXPECT_EQ(m.first, 0);
  EXPECT_TRUE(e.run(Algorithm::Centralized, w).empty()) << "simultaneous states never show 0 and 1";
}

TEST(DistributedDetector, OnlyLinearChainsInSlotOrder) {
  // A star: 0 in the centre. Chains a-b-c must walk edges: centre in the middle.
  TestEnsemble e(4, {"x"});
  for (int t = 0; t < 3; ++t) {
    e.set(t, 0, {{"x", 0}}, {1, 2, 3});
    for (uint32_t m = 1; m < 4; ++m) e.set(t, m, {{"x", 1}}, {0});
  }
  const Watchpoint w = compile_or_die("modules(a b c); (a.x = 1) and (c.x = 1)");
  const auto d = e.run(Algorithm::Distributed, w);
  EXPECT_EQ(d.size(), 6u);  // ordered pairs of leaves, through the centre
  for (const Match& m : d) EXPECT_EQ(m.second[1], 0u);
  const Watchpoint v = compile_or_die("modules(a b c); (b.x = 1) and (c.x = 1)");
  EXPECT_TRUE(e.run(Algorithm::Distributed, v).empty()) << "b-centre-c would need c after a";
  EXPECT_EQ(e.run(Algorithm::Centralized, v).size(), 6u * 3)
      << "Alg. 1 finds a = centre, b and c two leaves, every step";
}

TEST(DistributedDetector, NeverSendsBackToAModuleAlreadyInThePatternMatcher) {
  const auto e = ring(2, 3, [](int, uint32_t) { return 0; });  // 0 and 1 list each other twice over
  const Watchpoint w = compile_or_die("modules(a b c); (a.x = 0)");
  EXPECT_TRUE(e.run(Algorithm::Distributed, w).empty());
}

TEST(DistributedDetector, AModuleThatLeavesDropsWhatArrives) {
  TestEnsemble e(2, {"x"});
  e.set(0, 0, {{"x", 1}}, {1});
  e.set(0, 1, {{"x", 1}}, {0});
  e.set(1, 0, {{"x", 1}}, {});
  // 1 is absent at step 1: the PatternMatcher 0 sent it at step 0 is never filled.
  e.set(2, 0, {{"x", 1}}, {});
  const Watchpoint w = compile_or_die("modules(a b); (a.x = 1)");
  // Only 1's PatternMatcher, sent to 0 at step 0, is filled: 0 is still there at step 1.
  EXPECT_EQ(e.run(Algorithm::Distributed, w), (std::set<Match>{{0, {1, 0}}}));
}

TEST(DistributedDetector, MatchesAreReportedWithTheStartStepAfterExtentPlusMore) {
  const auto e = ring(3, 6, [](int t, uint32_t m) { return (t + static_cast<int>(m)) % 3; });
  const Watchpoint w = compile_or_die("modules(a b); (a.x = 0) and (b.next.x = 0)");
  const auto matches = e.run(Algorithm::Distributed, w);
  ASSERT_FALSE(matches.empty());
  for (const Match& m : matches) {
    const int64_t t0 = m.first;
    // a fills at t0, b at t0 + 1 and reads its x at t0 + 2; all must exist in 6 steps.
    EXPECT_LE(t0 + 2, 5);
    EXPECT_EQ((t0 + m.second[0]) % 3, 0);
    EXPECT_EQ((t0 + 2 + m.second[1]) % 3, 0);
  }
}

TEST(DistributedDetector, CarriedNeighbourSetDecidesNeighbor) {
  // Triangle 0-1-2 plus 3 hanging off 2. neighbor(a c) closes a triangle.
  TestEnsemble e(4, {"x"});
  for (int t = 0; t < 3; ++t) {
    e.set(t, 0, {{"x", 0}}, {1, 2});
    e.set(t, 1, {{"x", 0}}, {0, 2});
    e.set(t, 2, {{"x", 0}}, {0, 1, 3});
    e.set(t, 3, {{"x", 0}}, {2});
  }
  const Watchpoint w = compile_or_die("modules(a b c); neighbor(a c)");
  for (const auto& opt : testing::all_optimization_combinations()) {
    const auto matches = e.run(Algorithm::Distributed, w, {opt, 0});
    EXPECT_EQ(matches.size(), 6u * 1);  // the 6 orderings of the triangle, at t0 = 0
    for (const Match& m : matches) EXPECT_NE(m.second[2], 3u);
  }
}

TEST(DistributedDetector, CullingSendsFewerPatternMatchersWithIdenticalMatches) {
  TestEnsemble e(4, {"x"});
  for (int t = 0; t < 4; ++t) {
    e.set(t, 0, {{"x", 0}}, {1, 2});
    e.set(t, 1, {{"x", 0}}, {0, 2});
    e.set(t, 2, {{"x", 0}}, {0, 1, 3});
    e.set(t, 3, {{"x", 0}}, {2});
  }
  const Watchpoint w = compile_or_die("modules(a b c d); neighbor(a c) and neighbor(b d)");
  DetectorStats with, without;
  DetectorOptions on, off;
  off.optimizations.neighbor_culling = false;
  EXPECT_EQ(e.run(Algorithm::Distributed, w, on, &with), e.run(Algorithm::Distributed, w, off, &without));
  EXPECT_LT(with.messages, without.messages);
}

TEST(DistributedDetector, EarlyTerminationSendsFewerPatternMatchers) {
  const auto e = ring(6, 5, [](int t, uint32_t m) { return (t * 7 + static_cast<int>(m) * 3) % 4; });
  const Watchpoint w = compile_or_die("modules(a b c); (a.x = 0) and (c.x = 1)");
  DetectorStats with, without;
  DetectorOptions on, off;
  off.optimizations.early_termination = false;
  EXPECT_EQ(e.run(Algorithm::Distributed, w, on, &with), e.run(Algorithm::Distributed, w, off, &without));
  EXPECT_LT(with.created, without.created);
}

TEST(DistributedDetector, TemporalSpansKeepOnlyTheNeededHistory) {
  const auto e = ring(5, 20, [](int t, uint32_t m) { return (t + static_cast<int>(m)) % 2; });
  const Watchpoint w = compile_or_die("modules(a x b); (x.x = 1) and (a.last.x = 0)");
  DetectorStats with, without;
  DetectorOptions on, off;
  off.optimizations.temporal_spans = false;
  EXPECT_EQ(e.run(Algorithm::Distributed, w, on, &with), e.run(Algorithm::Distributed, w, off, &without));
  // Spans: x at -1..0 is 2 values, neighbour sets 1 step: 3 per module. Without: all 20 steps, twice.
  EXPECT_EQ(with.history_values, 5u * 3);
  EXPECT_EQ(without.history_values, 5u * 20 * 2);
}

TEST(DistributedDetector, BudgetStopsCleanly) {
  const auto e = ring(50, 10, [](int, uint32_t) { return 0; });
  const Watchpoint w = compile_or_die("modules(a b c d e f); (a.x = 0)");
  DetectorOptions o;
  o.live_budget = 300;
  DetectorStats st;
  e.run(Algorithm::Distributed, w, o, &st);
  EXPECT_TRUE(st.stopped);
  EXPECT_LE(st.peak_live, 300u);
  EXPECT_NE(st.stop_reason.find("300"), std::string::npos);
}

TEST(DistributedDetector, StatisticsFollowTheChains) {
  // Ring of 4, one-slot-per-step growth: per step 4 starts, 8 two-slot, 8 three-slot chains.
  const auto e = ring(4, 3, [](int, uint32_t) { return 0; });
  const Watchpoint w = compile_or_die("modules(a b c); (a.x = 0)");
  DetectorStats st;
  const auto matches = e.run(Algorithm::Distributed, w, {}, &st);
  EXPECT_EQ(matches.size(), 8u);  // only t0 = 0 completes within 3 steps
  ASSERT_EQ(st.created_by_filled.size(), 4u);
  EXPECT_EQ(st.created_by_filled[1], 12u);
  EXPECT_EQ(st.created_by_filled[2], 16u);
  EXPECT_EQ(st.created_by_filled[3], 8u);
  EXPECT_EQ(st.messages, 12u * 2 + 16u);  // every 1-slot PM to 2 neighbours, every 2-slot to 1
}

TEST(DistributedDetector, APatternMatcherEndingOnAFalseOwnLeafIsCountedAsTheSearchCountsIt) {
  // x = 0 1 2 0 1 2 0 1 around a ring of 8, the same every step. Per step: 8 starts; the three
  // with a.x = 0 reach 6 b's, of which 4 have b.x != 2 and each reach one c; c.x < 2 at 2 of them.
  // The PatternMatchers that end at a false own leaf are counted though nothing is filled.
  const auto e = ring(8, 6, [](int, uint32_t m) { return static_cast<int>(m % 3); });
  const Watchpoint w = compile_or_die("modules(a b c); (a.x = 0) and (b.x != 2) and (c.x < 2)");
  DetectorStats distributed, centralized;
  DetectorOptions chain;
  chain.shape = GroupShape::Chain;
  const auto by_agents = e.run(Algorithm::Distributed, w, {}, &distributed);
  const auto by_search = e.run(Algorithm::Centralized, w, chain, &centralized);
  EXPECT_EQ(by_agents.size(), 2u * 4);  // t0 = 0..3 complete within 6 steps
  EXPECT_EQ(by_search.size(), 2u * 6);
  for (const DetectorStats* st : {&distributed, &centralized}) {
    const auto step3 = std::find_if(st->steps.begin(), st->steps.end(), [](const StepStats& s) { return s.step == 3; });
    ASSERT_NE(step3, st->steps.end());
    EXPECT_EQ(step3->live_by_filled, (std::vector<uint64_t>{0, 8, 6, 4}));
    EXPECT_EQ(step3->matches, 2u);
  }
}

}  // namespace
}  // namespace dw::watch
