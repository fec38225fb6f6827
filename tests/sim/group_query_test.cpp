// Searching the history (sim/group_query.h): a change found back and on equals the nearest change
// in a straight run's values; a condition on a pair of neighbours holds at exactly the steps a
// centralized watchpoint with its text matches that pair (windows, offsets, an aggregate); the
// search for it finds the nearest of those steps; and both, on 1 and 2 threads, with keyframes far
// apart, leave the cursor where it was.
#include "sim/group_query.h"

#include <gtest/gtest.h>

#include <set>

#include "sim/session.h"
#include "tests/sim/test_programs.h"

namespace dw::sim {
namespace {

using test_programs::gossip_model;

constexpr int64_t kSteps = 90;  // longer than the first window, so that a search grows it

// The nearest step of `steps` before t (back) or after it.
std::optional<int64_t> nearest(const std::set<int64_t>& steps, int64_t t, bool back) {
  if (back) {
    auto it = steps.lower_bound(t);
    if (it == steps.begin()) return std::nullopt;
    return *--it;
  }
  auto it = steps.upper_bound(t);
  if (it == steps.end()) return std::nullopt;
  return *it;
}

TEST(GroupQuery, AChangeFoundBackAndOnIsTheNearestChangeOfAStraightRun) {
  const auto model = gossip_model({LatticeKind::Cubic, {4, 3, 2}}, {}, 3);
  std::vector<std::vector<int64_t>> values;  // [step]
  {
    StaticLatticeWorld world;
    Session straight(*model, world, {});
    straight.run_until(kSteps, [&](const State& s, const StepOutput&) { values.push_back(s.values); });
  }
  const size_t variables = model->variable_count();
  for (unsigned threads : {1u, 2u}) {
    StaticLatticeWorld world;
    // A small budget: keyframes far apart, so that windows start between them.
    Session session(*model, world, {.threads = threads, .history_bytes = 16 << 10});
    session.run_until(kSteps);
    for (ModuleId m : {0u, 11u, 23u})
      for (int column : {0, 2}) {
        std::set<int64_t> changes{0};
        for (int64_t s = 1; s < kSteps; ++s)
          if (values[size_t(s)][m * variables + size_t(column)] !=
              values[size_t(s - 1)][m * variables + size_t(column)])
            changes.insert(s);
        ASSERT_GT(changes.size(), 3u);
        for (int64_t t : {int64_t{0}, int64_t{5}, int64_t{47}, kSteps - 1}) {
          ASSERT_TRUE(session.seek(t));
          for (bool back : {true, false}) {
            const Found found = find_change(session, m, column, back ? SearchDirection::Back : SearchDirection::On, {});
            EXPECT_FALSE(found.cancelled);
            EXPECT_EQ(found.step, nearest(changes, t, back))
                << "module " << m << " column " << column << " from " << t << (back ? " back" : " on");
            EXPECT_EQ(session.current(), t);
          }
        }
      }
  }
}

TEST(GroupQuery, AConditionHoldsOnAPairWhereAWatchpointWithItsTextMatchesThatPair) {
  // A window kept by each module in a watch (times over a's own v), written out here; an offset;
  // an aggregate over a's neighbours.
  const std::string text =
      "modules(a b); times[4](a.v = 0) >= 2 and a.last.v != b.v and count(n in neighbors(a): n.v < 2) >= 2";
  const auto model = gossip_model({LatticeKind::Cubic, {4, 3, 2}}, {{text, watch::Algorithm::Centralized}}, 5);
  StaticLatticeWorld world;
  Session session(*model, world, {.threads = 2, .history_bytes = 16 << 10});
  session.run_until(kSteps);
  auto compiled = watch::compile_watchpoint("c", watch::SourceText("<test>", text), watch::WindowKeeping::WrittenOut);
  const watch::Program& program = std::get<watch::Watchpoint>(compiled).program;
  ASSERT_EQ(program.kept_columns, 0);
  ASSERT_GT(model->watches[0].watchpoint.program.kept_columns, 0);  // the watch keeps its window
  ASSERT_EQ(why_undecidable(program, 2), "");
  EXPECT_NE(why_undecidable(program, 3), "");
  const MatchList& list = session.matches(0);
  ASSERT_GT(list.size(), 10u);
  int pairs = 0;
  for (const auto& [a, b] : {std::pair<ModuleId, ModuleId>{0, 1}, {5, 4}, {13, 1}, {1, 13}, {22, 23}}) {
    std::set<int64_t> matched;
    for (size_t i = 0; i < list.size(); ++i)
      if (list.slots[2 * i] == a && list.slots[2 * i + 1] == b) matched.insert(list.t[i]);
    const ModuleId group[] = {a, b};
    session.seek(30);
    const auto truths = truth_over(session, program, group, 0, kSteps - 1, {});
    ASSERT_TRUE(truths);
    EXPECT_EQ(session.current(), 30);
    std::set<int64_t> held;
    for (int64_t s = 0; s < kSteps; ++s)
      if ((*truths)[size_t(s)] == watch::kTrue) held.insert(s);
    EXPECT_EQ(held, matched) << "pair " << a << " " << b;
    pairs += !held.empty();
    for (int64_t t : {int64_t{0}, int64_t{30}, int64_t{70}}) {
      session.seek(t);
      for (bool back : {true, false}) {
        const Found found =
            find_holding(session, program, group, back ? SearchDirection::Back : SearchDirection::On, {});
        EXPECT_EQ(found.step, nearest(held, t, back)) << "pair " << a << " " << b << " from " << t;
        EXPECT_EQ(session.current(), t);
      }
    }
  }
  EXPECT_GE(pairs, 2);  // the test looks at pairs that do match
}

TEST(GroupQuery, ASearchCancelledSaysSoAndLeavesTheCursor) {
  const auto model = gossip_model({LatticeKind::Cubic, {3, 3, 1}}, {}, 2);
  StaticLatticeWorld world;
  Session session(*model, world, {});
  session.run_until(40);
  session.seek(20);
  std::stop_source stop;
  stop.request_stop();
  const Found found = find_change(session, 4, 0, SearchDirection::Back, {.stop = stop.get_token()});
  EXPECT_TRUE(found.cancelled);
  EXPECT_FALSE(found.step);
  EXPECT_EQ(session.current(), 20);
}

// A session that keeps no history has nothing to search: none found, nothing read out of range.
TEST(GroupQuery, WithoutHistoryNothingIsFound) {
  const auto model = gossip_model({LatticeKind::Cubic, {3, 3, 1}}, {}, 2);
  StaticLatticeWorld world;
  Session session(*model, world, {.history_bytes = 0});
  session.run_until(30);
  for (const auto direction : {SearchDirection::Back, SearchDirection::On}) {
    const Found found = find_change(session, 4, 0, direction, {});
    EXPECT_FALSE(found.step);
    EXPECT_FALSE(found.cancelled);
  }
}

}  // namespace
}  // namespace dw::sim
