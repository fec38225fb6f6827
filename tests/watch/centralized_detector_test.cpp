#include "watch/centralized_detector.h"

#include <gtest/gtest.h>

#include "test_ensemble.h"

namespace dw::watch {
namespace {

using testing::compile_or_die;
using testing::Match;
using testing::TestEnsemble;

// A line 0-1-2-3 (undirected), one step.
TestEnsemble line4(std::vector<int64_t> leader) {
  TestEnsemble e(4, {"isLeader"});
  e.set(0, 0, {{"isLeader", leader[0]}}, {1});
  e.set(0, 1, {{"isLeader", leader[1]}}, {0, 2});
  e.set(0, 2, {{"isLeader", leader[2]}}, {1, 3});
  e.set(0, 3, {{"isLeader", leader[3]}}, {2});
  return e;
}

TEST(CentralizedDetector, Figure2FindsLeadersTwoHopsApartInBothOrders) {
  const Watchpoint w = compile_or_die("modules(a b c);(a.isLeader = 1) and (c.isLeader = 1)");
  const auto matches = line4({1, 0, 1, 0}).run(Algorithm::Centralized, w);
  EXPECT_EQ(matches, (std::set<Match>{{0, {0, 1, 2}}, {0, {2, 1, 0}}}));
}

TEST(CentralizedDetector, PrefixConnectedBindingsIncludeNonLinearOrders) {
  // Alg. 1 grows from every filled slot: c may hang off a (a star b-a-c).
  const Watchpoint w = compile_or_die("modules(a b c); (b.isLeader = 1) and (c.isLeader = 1)");
  const auto matches = line4({0, 1, 0, 1}).run(Algorithm::Centralized, w);
  // Leaders 1 and 3 share neighbour 2: a = 2 with b, c = 1, 3 in either order.
  EXPECT_EQ(matches, (std::set<Match>{{0, {2, 1, 3}}, {0, {2, 3, 1}}}));
}

TEST(CentralizedDetector, ConnectedSubsetsOfOneSlotMatchEachPresentModule) {
  const Watchpoint w = compile_or_die("modules(a); (a.isLeader = 1)");
  EXPECT_EQ(line4({1, 1, 0, 1}).run(Algorithm::Centralized, w), (std::set<Match>{{0, {0}}, {0, {1}}, {0, {3}}}));
}

TEST(CentralizedDetector, AbsentModulesAreNeverBound) {
  TestEnsemble e(3, {"x"});
  e.set(0, 0, {{"x", 1}}, {1, 2});  // 2 is listed but absent
  e.set(0, 1, {{"x", 1}}, {0});
  const Watchpoint w = compile_or_die("modules(a b); (a.x = 1) and (b.x = 1)");
  EXPECT_EQ(e.run(Algorithm::Centralized, w), (std::set<Match>{{0, {0, 1}}, {0, {1, 0}}}));
}

TEST(CentralizedDetector, NextDelaysTheDecisionAndReadsTheFuture) {
  TestEnsemble e(2, {"x"});
  for (int t = 0; t < 3; ++t) {
    e.set(t, 0, {{"x", t}}, {1});
    e.set(t, 1, {{"x", 10 + t}}, {0});
  }
  const Watchpoint w = compile_or_die("modules(a b); (a.next.x = 2) and (b.x = 11)");
  // t = 1: a.next.x is x at 2 = 2, b.x at 1 = 11. t = 2 is never decided: step 3 does not exist.
  EXPECT_EQ(e.run(Algorithm::Centralized, w), (std::set<Match>{{1, {0, 1}}}));
}

TEST(CentralizedDetector, UnknownIsNeverAMatchButNotOfUnknownCanBe) {
  TestEnsemble e(2, {"x", "y"});
  e.set(0, 0, {{"x", 1}}, {1});
  e.set(0, 1, {{"y", 1}}, {0});  // lacks x
  const Watchpoint unknown = compile_or_die("modules(a b); (a.x = 1) and (b.x = 1)");
  EXPECT_TRUE(e.run(Algorithm::Centralized, unknown).empty());
  const Watchpoint shortcut = compile_or_die("modules(a b); (a.x = 1) or (b.x = 1)");
  // (0 1): a.x = 1. (1 0): a.x is unknown, but b.x = 1 makes the or true.
  EXPECT_EQ(e.run(Algorithm::Centralized, shortcut), (std::set<Match>{{0, {0, 1}}, {0, {1, 0}}}));
  const Watchpoint negated = compile_or_die("modules(a b); not (b.x = 1)");
  EXPECT_TRUE(e.run(Algorithm::Centralized, negated).empty()) << "not U is U";
}

TEST(CentralizedDetector, LastBeforeStepZeroIsUnknown) {
  TestEnsemble e(1, {"x"});
  e.set(0, 0, {{"x", 5}}, {});
  e.set(1, 0, {{"x", 5}}, {});
  const Watchpoint w = compile_or_die("modules(a); not (a.last.x != a.x)");
  EXPECT_EQ(e.run(Algorithm::Centralized, w), (std::set<Match>{{1, {0}}}));
}

TEST(CentralizedDetector, NeighborReadsTheDirectedGraphAtItsOffset) {
  TestEnsemble e(3, {"x"});
  e.set(0, 0, {{"x", 0}}, {1, 2});
  e.set(0, 1, {{"x", 0}}, {0});
  e.set(0, 2, {{"x", 0}}, {0});  // 2 -> 0 only
  e.set(1, 0, {{"x", 0}}, {1});
  e.set(1, 1, {{"x", 0}}, {0, 2});
  e.set(1, 2, {{"x", 0}}, {1});
  const Watchpoint w = compile_or_die("modules(a b); neighbor(a.last b.last)");
  // At t = 1 the bindings are pairs adjacent at 1; neighbor() asks about step 0.
  EXPECT_EQ(e.run(Algorithm::Centralized, w), (std::set<Match>{{1, {0, 1}}, {1, {1, 0}}}));
}

// `any` groups are grown by enumeration before any binding is tried: a watchpoint whose groups
// can never be completed (no module takes its last slot) grew groups for hours over a 6^3
// lattice with 12 slots. The groups grown meet the budget as the bindings do.
TEST(CentralizedDetector, GrowingAnyGroupsMeetsTheBudget) {
  TestEnsemble e(36, {"x"});
  for (uint32_t m = 0; m < 36; ++m) {  // a 6 x 6 grid
    std::vector<uint32_t> n;
    if (m % 6 > 0) n.push_back(m - 1);
    if (m % 6 < 5) n.push_back(m + 1);
    if (m >= 6) n.push_back(m - 6);
    if (m < 30) n.push_back(m + 6);
    e.set(0, m, {{"x", 1}}, n);
  }
  // Every module may take a, so every module is eligible; none takes f, so no binding is tried.
  const Watchpoint w = compile_or_die("modules(a b c d e f); a.x >= 0 and f.x < 0");
  DetectorOptions o;
  o.shape = GroupShape::Any;
  o.live_budget = 50;
  DetectorStats st;
  EXPECT_TRUE(e.run(Algorithm::Centralized, w, o, &st).empty());
  EXPECT_TRUE(st.stopped);
  EXPECT_NE(st.stop_reason.find("more than 50 connected groups grown at watch step 0"), std::string::npos)
      << st.stop_reason;
  o.live_budget = 0;
  DetectorStats unbounded;
  EXPECT_TRUE(e.run(Algorithm::Centralized, w, o, &unbounded).empty());
  EXPECT_FALSE(unbounded.stopped);
}

TEST(CentralizedDetector, BudgetStopsTheRunAndKeepsEarlierMatches) {
  TestEnsemble e(4, {"isLeader"});
  e.set(0, 0, {{"isLeader", 1}}, {1});  // step 0: 2 + 2 fills
  e.set(0, 1, {{"isLeader", 1}}, {0});
  for (int t = 1; t < 3; ++t)  // then a ring: 4 + 8 fills a step
    for (uint32_t m = 0; m < 4; ++m) e.set(t, m, {{"isLeader", 1}}, {(m + 1) % 4, (m + 3) % 4});
  const Watchpoint w = compile_or_die("modules(a b); (a.isLeader = 1)");
  DetectorOptions o;
  o.live_budget = 10;
  DetectorStats st;
  const auto matches = e.run(Algorithm::Centralized, w, o, &st);
  EXPECT_TRUE(st.stopped);
  EXPECT_NE(st.stop_reason.find("10"), std::string::npos);
  EXPECT_NE(st.stop_reason.find("step 1"), std::string::npos);
  size_t at_zero = 0;
  for (const Match& m : matches) at_zero += m.first == 0;
  EXPECT_EQ(at_zero, 2u);
  EXPECT_EQ(matches.size(), at_zero) << "the step that went over the budget reports nothing";
  EXPECT_EQ(st.steps.size(), 1u) << "nor does it count; nothing runs after the stop";
}

TEST(CentralizedDetector, StatisticsCountFillsBySlot) {
  const Watchpoint w = compile_or_die("modules(a b c);(a.isLeader = 1) and (c.isLeader = 1)");
  DetectorStats st;
  line4({1, 0, 1, 0}).run(Algorithm::Centralized, w, {}, &st);
  // Early termination: only leaders 0 and 2 survive slot a; each has its neighbours for b.
  ASSERT_EQ(st.created_by_filled.size(), 4u);
  EXPECT_EQ(st.created_by_filled[1], 4u);
  EXPECT_EQ(st.created_by_filled[2], 3u);  // 0-1, 2-1, 2-3
  EXPECT_EQ(st.created_by_filled[3], 4u);  // 0-1-2, 2-1-0, 2-1-3, 2-3-1
  EXPECT_EQ(st.matches, 2u);
}

}  // namespace
}  // namespace dw::watch
