// A soak test of time travel (docs/design.md §7): 2,000 steps of a shipped scenario with 50 rollbacks to
// random depths in the snapshot ring, each followed by a resume. The state hash equals the straight
// run's at every step, after every rollback and at the end, and so do the matches, on 1 and 2
// threads: table1 with a second watchpoint that stops at its live budget part way (the stop is
// crossed back and forth), and push_wall, whose bonds break and modules fall (Bullet).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <random>
#include <sstream>

#include "scenarios/scenario.h"
#include "sim/session.h"
#include "sim/state.h"
#include "tests/sim/run_trail.h"

namespace dw::scenarios {
namespace {

constexpr int64_t kSteps = 2000;
constexpr size_t kRing = 64;

std::string file_text(const std::string& name) {
  std::ifstream in(std::string(DWATCH_SCENARIOS_DIR) + "/" + name);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Scenario load(const std::string& toml) {
  auto loaded = load_scenario_text("soak.toml", toml);
  if (auto* e = std::get_if<std::string>(&loaded)) ADD_FAILURE() << *e;
  return std::move(std::get<Scenario>(loaded));
}

// Returns the straight run's statistics of watch `w`, for what the caller expects of it.
watch::DetectorStats soak(const std::string& toml, unsigned threads, uint32_t seed, uint32_t w = 0) {
  Scenario s = load(toml);
  sim::Session straight(*s.model, *s.world, {.threads = threads});
  std::vector<uint64_t> expected;
  straight.run_until(
      kSteps, [&](const sim::State& st, const sim::StepOutput&) { expected.push_back(sim::hash_state(st).whole()); });
  EXPECT_EQ(expected.size(), size_t(kSteps));

  Scenario again = load(toml);
  sim::Session run(*again.model, *again.world, {.threads = threads});
  std::vector<uint64_t> hashes(kSteps, 0);
  const auto keep = [&](const sim::State& st, const sim::StepOutput& out) {
    hashes[size_t(out.step)] = sim::hash_state(st).whole();
  };
  std::mt19937 random(seed);
  for (int i = 1; i <= 50; ++i) {
    const int64_t at = kSteps * i / 51;
    while (run.current() + 1 < at) run.run_until(at, keep);
    // The ring holds the state before step 0 and those after the last kRing steps.
    const int64_t back = std::max<int64_t>(-1, at - 1 - int64_t(random() % kRing));
    EXPECT_TRUE(run.seek(back)) << "rollback " << i << " to step " << back;
    if (back >= 0) {
      EXPECT_EQ(sim::hash_state(run.state()).whole(), expected[size_t(back)]) << "restored step " << back;
    }
  }
  while (run.current() + 1 < kSteps) run.run_until(kSteps, keep);
  for (int64_t t = 0; t < kSteps; ++t) EXPECT_EQ(hashes[size_t(t)], expected[size_t(t)]) << "step " << t;
  EXPECT_EQ(sim::test::flat_matches(run), sim::test::flat_matches(straight));
  for (uint32_t w = 0; w < s.model->watches.size(); ++w) {
    EXPECT_EQ(run.match_count(w), straight.match_count(w));
    EXPECT_EQ(run.stats(w).stopped, straight.stats(w).stopped);
    EXPECT_EQ(run.stats(w).stop_reason, straight.stats(w).stop_reason);
  }
  return straight.stats(w);
}

TEST(TimeTravelSoak, Table1WithABudgetStopEqualsTheStraightRunAtEveryStep) {
  // The second watch's live PatternMatchers go over 19,950 first at detector step 1413.
  const std::string toml = file_text("table1.toml") +
                           "\n[[watch]]\nname = \"budget\"\n"
                           "text = \"modules(a b c); (a.x1 = 0) and (b.x2 = 0) and (c.x3 = 0)\"\n"
                           "algorithm = \"distributed\"\naction = \"count\"\nmax_live = 19950\n";
  // Two threads: the budget is shared by both (sim/watch_hosting.cpp), and the stop must not depend on it.
  const watch::DetectorStats budget = soak(toml, 2, 7, 1);
  EXPECT_TRUE(budget.stopped);
  EXPECT_NE(budget.stop_reason.find("detector step 1413"), std::string::npos) << budget.stop_reason;
}

TEST(TimeTravelSoak, PushWallEqualsTheStraightRunAtEveryStep) {
  const std::string toml = file_text("push_wall.toml");
  soak(toml, 1, 9);
  soak(toml, 2, 10);
}

}  // namespace
}  // namespace dw::scenarios
