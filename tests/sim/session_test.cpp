// Snapshots, rollback and resume (DESIGN §7), and thread-count independence: a resumed run equals
// one that never rolled back, hash for hash at every step, and so do runs on 1, 2 and 3 threads.
#include "sim/session.h"

#include <gtest/gtest.h>

#include "sim/state.h"
#include "tests/sim/run_trail.h"
#include "tests/sim/test_programs.h"

namespace dw::sim {
namespace {

using test_programs::gossip_model;

const std::vector<std::pair<std::string, watch::Algorithm>> kWatches{
    {"modules(a b c); (a.v = 1) and (b.v = 2) and (c.mix > b.mix)", watch::Algorithm::Distributed},
    {"modules(a b c); (a.v = 1) and (b.v = 2) and (c.mix > b.mix)", watch::Algorithm::Centralized},
    {"modules(a b); (a.v = 3) and (b.next.v = 3) and (a.last.v = 0)", watch::Algorithm::Distributed},
};

using test::Trail;

Trail collect(const sim::Session& run) { return Trail{{}, test::flat_matches(run)}; }

Trail straight_run(const Model& model, unsigned threads, int64_t steps) {
  StaticLatticeWorld world;
  sim::Session run(model, world, {.threads = threads});
  std::vector<uint64_t> hashes;
  run.run_until(steps, [&](const State& s, const StepOutput&) { hashes.push_back(hash_state(s)); });
  Trail t = collect(run);
  t.hashes = std::move(hashes);
  return t;
}

TEST(Run, ResumedRunEqualsUninterruptedRunAtEveryStep) {
  const auto model = gossip_model({LatticeKind::Cubic, {6, 5, 4}}, kWatches);
  const Trail straight = straight_run(*model, 1, 60);
  ASSERT_EQ(straight.hashes.size(), 60u);
  for (size_t w = 0; w < 3; ++w) EXPECT_FALSE(straight.matches[w].empty()) << "watch " << w << " should match";

  StaticLatticeWorld world;
  sim::Session run(*model, world, {.threads = 1});
  std::vector<uint64_t> hashes(60);
  const auto keep = [&](const State& s, const StepOutput& out) { hashes[size_t(out.step)] = hash_state(s); };
  run.run_until(45, keep);
  ASSERT_TRUE(run.seek(30));
  EXPECT_EQ(run.current() + 1, 31);
  EXPECT_EQ(hash_state(run.state()), straight.hashes[30]);
  // The matches found after step 30 are forgotten...
  for (uint32_t w = 0; w < 3; ++w)
    for (int64_t d : run.matches(w).detected) EXPECT_LE(d, 30);
  // ...and found again on the way back.
  run.run_until(60, keep);
  EXPECT_EQ(hashes, straight.hashes);
  const Trail resumed = collect(run);
  EXPECT_EQ(resumed.matches, straight.matches);
  for (uint32_t w = 0; w < 3; ++w) EXPECT_EQ(run.match_count(w), straight.matches[w].size() / (w == 2 ? 3 : 4));
}

TEST(Run, RollbackTwiceAndToTheStart) {
  const auto model = gossip_model({LatticeKind::Hex2d, {7, 6, 1}}, kWatches);
  const Trail straight = straight_run(*model, 1, 30);
  StaticLatticeWorld world;
  sim::Session run(*model, world, {.threads = 2});
  run.run_until(30);
  ASSERT_TRUE(run.seek(20));
  ASSERT_TRUE(run.seek(5));
  EXPECT_FALSE(run.seek(25)) << "the future after step 5 is gone";
  ASSERT_TRUE(run.seek(-1));
  EXPECT_EQ(run.current() + 1, 0);
  std::vector<uint64_t> hashes;
  run.run_until(30, [&](const State& s, const StepOutput&) { hashes.push_back(hash_state(s)); });
  EXPECT_EQ(hashes, straight.hashes);
  EXPECT_EQ(collect(run).matches, straight.matches);
}

TEST(Run, SnapshotsReachBackExactlyK) {
  const auto model = gossip_model({LatticeKind::Ring, {10, 1, 1}}, {});
  StaticLatticeWorld world;
  sim::Session run(*model, world, {.threads = 1});
  run.run_until(12);
  EXPECT_EQ(run.oldest_snapshot(), 6);
  EXPECT_FALSE(run.seek(5));
  EXPECT_TRUE(run.seek(6));
  sim::Session none(*model, world, {.threads = 1});
  none.run_until(3);
  EXPECT_FALSE(none.oldest_snapshot());
  EXPECT_FALSE(none.seek(2));
}

// A watch stopped at its live budget leaves nothing behind in the runtime: rolled back to before
// the stop and resumed, the run stops at the same step with the same hashes as the straight run.
TEST(Run, BudgetStopRolledBackAndResumedEqualsTheStraightRun) {
  // `count` grows by about one a step, so PatternMatchers pile up only after step 20 or so.
  const std::string text = "modules(a b c); (a.count > 30) and (b.count > 30) and (c.mix > b.mix)";
  auto model = gossip_model({LatticeKind::Cubic, {6, 5, 4}},
                            {{text, watch::Algorithm::Distributed}, {text, watch::Algorithm::Centralized}});
  for (const HostedWatchpoint& h : model->watches) const_cast<HostedWatchpoint&>(h).options.live_budget = 400;
  std::vector<uint64_t> first;  // the 1-thread run's hashes: the stop never depends on threads
  for (unsigned threads : {1u, 2u, 3u}) {
    StaticLatticeWorld world;
    sim::Session straight(*model, world, {.threads = threads});
    std::vector<uint64_t> expected;
    straight.run_until(40, [&](const State& s, const StepOutput&) { expected.push_back(hash_state(s)); });
    for (uint32_t w : {0u, 1u}) {
      ASSERT_TRUE(straight.stats(w).stopped) << "watch " << w << " should hit its budget";
      EXPECT_GE(straight.stats(w).steps.size(), 20u) << "late, not at once: " << straight.stats(w).stop_reason;
    }
    EXPECT_FALSE(straight.matches(0).t.empty()) << "matches before the stop are kept";
    if (first.empty()) first = expected;
    EXPECT_EQ(expected, first) << threads << " threads";

    sim::Session run(*model, world, {.threads = threads});
    std::vector<uint64_t> hashes(40);
    const auto keep = [&](const State& s, const StepOutput& out) { hashes[size_t(out.step)] = hash_state(s); };
    run.run_until(40, keep);
    for (int64_t back : {19, 12, 2, -1}) {  // each before the budget stop
      ASSERT_TRUE(run.seek(back));
      EXPECT_FALSE(run.stats(0).stopped) << "rolled back to step " << back;
      run.run_until(40, keep);
      EXPECT_EQ(hashes, expected) << "resumed after a rollback to step " << back << ", " << threads << " threads";
      EXPECT_EQ(run.stats(0).stop_reason, straight.stats(0).stop_reason);
      EXPECT_EQ(test::flat_matches(run), test::flat_matches(straight));
    }
  }
}

TEST(Run, ThreadCountNeverChangesResults) {
  const auto model = gossip_model({LatticeKind::Cubic, {7, 6, 5}}, kWatches, 42);
  const Trail one = straight_run(*model, 1, 40);
  for (unsigned threads : {2u, 3u, 8u}) {
    const Trail many = straight_run(*model, threads, 40);
    EXPECT_EQ(many.hashes, one.hashes) << threads << " threads";
    EXPECT_EQ(many.matches, one.matches) << threads << " threads";
  }
}

TEST(Run, SeedChangesTheRun) {
  const auto a = gossip_model({LatticeKind::Line, {20, 1, 1}}, {}, 1);
  const auto b = gossip_model({LatticeKind::Line, {20, 1, 1}}, {}, 2);
  EXPECT_NE(straight_run(*a, 1, 10).hashes, straight_run(*b, 1, 10).hashes);
  EXPECT_EQ(straight_run(*a, 1, 10).hashes, straight_run(*a, 1, 10).hashes);
}

TEST(Run, PauseStopsAtTheMatchAndFiresOncePerDetection) {
  std::vector<std::pair<std::string, watch::Algorithm>> w{
      {"modules(a b); (a.v = 1) and (b.v = 1)", watch::Algorithm::Distributed}};
  auto model = gossip_model({LatticeKind::Square2d, {5, 5, 1}}, w);
  const_cast<HostedWatchpoint&>(model->watches[0]).action = MatchAction::Pause;
  StaticLatticeWorld world;
  sim::Session run(*model, world, {.threads = 1});
  const auto pause = run.run_until(50);
  ASSERT_TRUE(pause);
  EXPECT_EQ(pause->detected, run.current() + 1 - 1);
  EXPECT_EQ(pause->t, pause->detected - 1) << "two slots: found one step after it started";
  EXPECT_EQ(pause->group.size(), 2u);
  // Rolled back to the match's step and resumed, the run goes on past it.
  ASSERT_TRUE(run.seek(pause->t));
  const auto next = run.run_until(50);
  if (next) {
    EXPECT_GT(next->detected, pause->detected);
  }
}

}  // namespace
}  // namespace dw::sim
