// Watchpoints' actions (docs/design.md §4b) as a run carries them out: LDP's one-line gradient
// (scenarios/gradient_ldp.toml) ends at the BFS distances; the same states on any thread count;
// and an action takes effect at the start of step t + λ + 1, whichever reading found the match.
#include <gtest/gtest.h>

#include <deque>
#include <optional>
#include <set>
#include <sstream>

#include "scenarios/scenario.h"
#include "sim/session.h"
#include "sim/state.h"

namespace dw::scenarios {
namespace {

Scenario load(const std::string& path, ScenarioOverrides overrides = {}) {
  auto loaded = load_scenario(path, overrides);
  if (auto* e = std::get_if<std::string>(&loaded)) ADD_FAILURE() << *e;
  return std::move(std::get<Scenario>(loaded));
}

std::vector<int64_t> bfs(const sim::NeighborGraph& g, uint32_t root) {
  std::vector<int64_t> d(g.module_count(), -1);
  std::deque<uint32_t> queue{root};
  d[root] = 0;
  while (!queue.empty()) {
    const uint32_t m = queue.front();
    queue.pop_front();
    for (uint32_t n : g.neighbors(m))
      if (d[n] < 0) {
        d[n] = d[m] + 1;
        queue.push_back(n);
      }
  }
  return d;
}

TEST(WatchActions, TheLdpGradientEndsAtTheBreadthFirstDistances) {
  for (auto algorithm : {watch::Algorithm::Centralized, watch::Algorithm::Distributed}) {
    ScenarioOverrides o;
    o.algorithm = algorithm;
    Scenario s = load(DWATCH_SCENARIOS_DIR "/gradient_ldp.toml", o);
    sim::Session session(*s.model, *s.world, {.threads = 2, .end = s.steps});
    session.run_until(s.steps);
    const int column = s.model->column("dist");
    const std::vector<int64_t> want = bfs(*s.model->lattice.graph, 65);
    const sim::State& state = session.state();
    const size_t v = s.model->variable_count();
    for (uint32_t m = 0; m < s.model->module_count(); ++m)
      ASSERT_EQ(state.values[m * v + static_cast<size_t>(column)], want[m])
          << "module " << m << ", " << watch::algorithm_name(algorithm);
    EXPECT_GT(state.watches[0].actions_done, 0u);
    EXPECT_EQ(state.watches[0].actions_skipped, 0u);
  }
}

// scenarios/bfs_tree_ldp.toml: the gradient's distances, and `argmin` over the neighbours' (ties to
// the least id) as each module's parent, give a breadth-first spanning tree: every parent one hop
// nearer the root, the least such id, the root its own; in both readings.
TEST(WatchActions, ArgminBuildsTheBreadthFirstTreeTiesToTheLeastId) {
  for (auto algorithm : {watch::Algorithm::Centralized, watch::Algorithm::Distributed}) {
    ScenarioOverrides o;
    o.algorithm = algorithm;
    Scenario s = load(DWATCH_SCENARIOS_DIR "/bfs_tree_ldp.toml", o);
    sim::Session session(*s.model, *s.world, {.threads = 2, .end = s.steps});
    session.run_until(s.steps);
    const sim::NeighborGraph& g = *s.model->lattice.graph;
    const std::vector<int64_t> dist = bfs(g, 65);
    const int column = s.model->column("parent");
    const size_t v = s.model->variable_count();
    const sim::State& state = session.state();
    int ties = 0;  // modules with two neighbours one hop nearer: the tie rule is what picks
    for (uint32_t m = 0; m < s.model->module_count(); ++m) {
      int64_t want = m;
      int nearer = 0;
      for (uint32_t n : g.neighbors(m))
        if (dist[n] == dist[m] - 1) {
          want = nearer++ == 0 ? n : std::min<int64_t>(want, n);
        }
      ties += nearer > 1;
      ASSERT_EQ(state.values[m * v + static_cast<size_t>(column)], want)
          << "module " << m << ", " << watch::algorithm_name(algorithm);
    }
    EXPECT_GT(ties, 10);
    EXPECT_GT(state.watches[1].actions_done, 0u);
  }
}

TEST(WatchActions, SameStatesOnOneAndTwoThreadsAndAfterASeekBackAndForth) {
  std::vector<uint64_t> hashes[2];
  for (unsigned threads : {1u, 2u}) {
    Scenario s = load(DWATCH_SCENARIOS_DIR "/gradient_ldp.toml");
    sim::Session session(*s.model, *s.world, {.threads = threads, .end = s.steps});
    session.run_until(s.steps, [&](const sim::State& st, const sim::StepOutput&) {
      hashes[threads - 1].push_back(sim::hash_state(st).whole());
    });
    if (threads == 2) {
      ASSERT_TRUE(session.seek(3));
      ASSERT_TRUE(session.seek(s.steps - 1));
      EXPECT_EQ(session.hash().whole(), hashes[1].back());
    }
  }
  EXPECT_EQ(hashes[0], hashes[1]);
}

// A module sets its own variable one step after its match is decided: the action step is
// t + λ + 1 in every reading, λ its lag (a two-slot chain read by the agents decides a step one
// step later; read over simultaneous states, after its latency).
TEST(WatchActions, AnActionActsAtTheStartOfStepTPlusLagPlusOneInEveryReading) {
  struct Reading {
    watch::Algorithm algorithm;
    std::optional<watch::States> states;
    const char* text;
  };
  const Reading readings[] = {
      {watch::Algorithm::Centralized, std::nullopt, "modules(a); a.dist = 0 then set a.dist = 7"},
      {watch::Algorithm::Distributed, std::nullopt, "modules(a b); a.dist = 0 then set a.dist = 7"},
      {watch::Algorithm::Distributed, watch::States::Simultaneous, "modules(a b c); a.dist = 0 then set a.dist = 7"},
  };
  std::set<int64_t> lags;
  for (const Reading& r : readings) {
    Scenario s = load(DWATCH_SCENARIOS_DIR "/gradient_ldp.toml");
    auto compiled = watch::compile_watchpoint("root", watch::SourceText("t", r.text));
    ASSERT_TRUE(std::holds_alternative<watch::Watchpoint>(compiled));
    sim::HostedWatchpoint h{std::get<watch::Watchpoint>(std::move(compiled)), r.algorithm, sim::MatchAction::Count, {}};
    h.options.states = r.states;
    s.model->watches = {std::move(h)};
    const int64_t lag = s.model->watches[0].lag();
    lags.insert(lag);
    sim::Session session(*s.model, *s.world, {.threads = 1, .end = 10});
    const int column = s.model->column("dist");
    const size_t v = s.model->variable_count();
    std::vector<int64_t> root_dist;
    session.run_until(10, [&](const sim::State& st, const sim::StepOutput&) {
      root_dist.push_back(st.values[65 * v + static_cast<size_t>(column)]);
    });
    // Matched at t = 0 (and on until it acts), decided at step λ, acting at the start of λ + 1.
    for (int64_t t = 0; t <= lag; ++t) EXPECT_EQ(root_dist[static_cast<size_t>(t)], 0) << "step " << t;
    EXPECT_EQ(root_dist[static_cast<size_t>(lag + 1)], 7) << r.text;
  }
  EXPECT_EQ(lags.size(), 3u) << "three readings, three lags";
}

// Fault injection (scenarios/token_ring_fault.toml): `drop` takes the token at module 5 the step
// it gets there; `lost` sees it gone two steps later, at module 5, and nowhere before.
TEST(WatchActions, AnInjectedFaultIsCaughtWhereAndWhenItHappens) {
  Scenario s = load(DWATCH_SCENARIOS_DIR "/token_ring_fault.toml");
  sim::Session session(*s.model, *s.world, {.threads = 1, .end = s.steps});
  const std::optional<sim::Pause> pause = session.run_until(s.steps);
  ASSERT_TRUE(pause.has_value());
  const sim::MatchList& drops = session.matches(0);
  ASSERT_GE(drops.size(), 1u);
  EXPECT_EQ(drops.slots[0], 5u);
  EXPECT_EQ(s.model->watches[pause->watch].watchpoint.name, "lost");
  EXPECT_EQ(pause->t, drops.t[0] + 2);
  EXPECT_EQ(pause->group[1], 5u);  // x, the module that held it
  EXPECT_EQ(session.state().watches[0].actions_done, 1u);
}

}  // namespace
}  // namespace dw::scenarios

namespace dw::scenarios {
namespace {

// A variable's history and a recorded trace are re-simulated from keyframes: the watchpoints
// with actions must act there too, or the values would be those of a run without them (and the
// re-simulation once crashed on their missing states).
TEST(WatchActions, ASessionsSeriesAndRecordGiveTheValuesTheRunHad) {
  for (auto algorithm : {watch::Algorithm::Centralized, watch::Algorithm::Distributed}) {
    ScenarioOverrides o;
    o.algorithm = algorithm;
    Scenario s = load(DWATCH_SCENARIOS_DIR "/gradient_ldp.toml", o);
    sim::Session session(*s.model, *s.world, {.end = 20});
    session.run_until(20);
    const int column = s.model->column("dist");
    const size_t v = s.model->variable_count();
    for (const sim::ModuleId m : {sim::ModuleId{0}, sim::ModuleId{100}}) {
      const auto series = session.series(m, column, 0, 19);
      ASSERT_TRUE(series);
      ASSERT_EQ(series->size(), 20u);
      for (int64_t t = 0; t < 20; ++t) {
        ASSERT_TRUE(session.seek(t));
        EXPECT_EQ((*series)[size_t(t)], session.state().values[m * v + size_t(column)])
            << "module " << m << " at step " << t << ", " << watch::algorithm_name(algorithm);
      }
    }
    std::ostringstream trace;
    ASSERT_EQ(session.record(trace), "");
    // The last frame's line of module 0 holds its distance at step 19, as the run had it.
    const std::string text = trace.str();
    const size_t last = text.rfind("{\"t\":19,\"m\":0,");
    ASSERT_NE(last, std::string::npos);
    ASSERT_TRUE(session.seek(19));
    const std::string dist = "\"dist\":" + std::to_string(session.state().values[size_t(column)]);
    EXPECT_EQ(text.substr(last, text.find('\n', last) - last).find(dist) != std::string::npos, true)
        << text.substr(last, 200);
  }
}

}  // namespace
}  // namespace dw::scenarios
