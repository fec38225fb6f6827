// The PatternMatcher budget of a whole run (watch::RunBudget, docs/cli.md): over all the
// watchpoints together, charged in watchpoint order; the one that passes it and those after it
// stop, the same on any thread count, and a watchpoint a session evaluates over its history stops
// where a run that had it last from step 0 stops it.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "sim/session.h"
#include "tests/sim/run_trail.h"
#include "tests/sim/test_programs.h"

namespace dw::sim {
namespace {

using test_programs::gossip_model;

// `count` grows by about one a step, so PatternMatchers pile up only after step 20 or so.
const std::string kGrowing = "modules(a b c); (a.count > 30) and (b.count > 30) and (c.mix > b.mix)";

struct Outcome {
  std::vector<std::string> reasons;  // per watchpoint: why it stopped, or ""
  std::vector<std::vector<int64_t>> matches;
  bool operator==(const Outcome&) const = default;
};

Outcome outcome_of(const Session& run) {
  Outcome o{{}, test::flat_matches(run)};
  for (uint32_t w = 0; w < run.watches().size(); ++w)
    o.reasons.push_back(run.stats(w).stopped ? run.stats(w).stop_reason : "");
  return o;
}

std::unique_ptr<Model> growing_model(size_t copies) {
  std::vector<std::pair<std::string, watch::Algorithm>> watches;
  for (size_t i = 0; i < copies; ++i)
    watches.push_back({kGrowing, i % 2 ? watch::Algorithm::Centralized : watch::Algorithm::Distributed});
  auto model = gossip_model({LatticeKind::Cubic, {6, 5, 4}}, watches);
  for (size_t i = 0; i < copies; ++i) {
    model->watches[i].watchpoint.name = "w" + std::to_string(i);
    model->watches[i].options.live_budget = 400;
  }
  return model;
}

Outcome run_with_budget(const Model& model, unsigned threads, uint64_t budget) {
  StaticLatticeWorld world;
  Session run(model, world, {.threads = threads, .run_live_budget = budget});
  run.run_until(40);
  return outcome_of(run);
}

TEST(RunBudget, StopsTheWatchpointThatPassesItAndThoseAfterOnAnyThreadCount) {
  const auto model = growing_model(4);
  const Outcome alone = run_with_budget(*model, 1, 0);
  for (const std::string& why : alone.reasons) EXPECT_NE(why.find("more than 400"), std::string::npos) << why;
  const Outcome shared = run_with_budget(*model, 1, 600);
  EXPECT_EQ(shared.reasons[0].find("whole run"), std::string::npos) << "the first is charged alone";
  for (size_t w = 1; w < shared.reasons.size(); ++w)
    EXPECT_NE(shared.reasons[w].find("the whole run's budget of 600"), std::string::npos)
        << w << ": " << shared.reasons[w];
  for (unsigned threads : {2u, 3u}) EXPECT_EQ(run_with_budget(*model, threads, 600), shared) << threads << " threads";
}

TEST(RunBudget, AWatchpointEvaluatedOverTheHistoryStopsAsIfItHadBeenThereLast) {
  const auto all = growing_model(3);
  const auto fewer = growing_model(2);
  for (unsigned threads : {1u, 2u}) {
    const Outcome straight = run_with_budget(*all, threads, 600);
    ASSERT_NE(straight.reasons[2], "");
    StaticLatticeWorld world;
    Session run(*fewer, world, {.threads = threads, .run_live_budget = 600});
    run.run_until(40);
    HostedWatchpoint added = all->watches[2];
    ASSERT_TRUE(run.set_watch(added));
    EXPECT_EQ(outcome_of(run), straight) << threads << " threads";
  }
}

}  // namespace
}  // namespace dw::sim
