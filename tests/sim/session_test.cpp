// The session (docs/design.md §7): the whole history, seek, branches, retroactive watchpoints, decided
// steps and cancelling. Every claim is checked against a straight run: state hashes at every
// step and the matches, on 1 and 2 (or more) threads.
#include "sim/session.h"

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <sstream>

#include "sim/state.h"
#include "sim/trace.h"
#include "tests/sim/run_trail.h"
#include "tests/sim/test_programs.h"

namespace dw::sim {
namespace {

using test::Trail;
using test_programs::gossip_model;

const std::vector<std::pair<std::string, watch::Algorithm>> kWatches{
    {"modules(a b c); (a.v = 1) and (b.v = 2) and (c.mix > b.mix)", watch::Algorithm::Distributed},
    {"modules(a b c); (a.v = 1) and (b.v = 2) and (c.mix > b.mix)", watch::Algorithm::Centralized},
    {"modules(a b); (a.v = 3) and (b.next.v = 3) and (a.last.v = 0)", watch::Algorithm::Distributed},
};

Trail straight_run(Model& model, unsigned threads, int64_t steps, std::vector<Intervention> events = {}) {
  StaticLatticeWorld world;
  Session run(model, world, {.threads = threads, .events = std::move(events)});
  std::vector<uint64_t> hashes, runs;
  run.run_until(steps, [&](const State& s, const StepOutput&) {
    const StateHash hash = hash_state(s);
    hashes.push_back(hash.whole());
    runs.push_back(hash.run);
  });
  return Trail{std::move(hashes), std::move(runs), test::flat_matches(run)};
}

// Seeks to every step of the session and compares its state hash (and its run hash, when `runs`
// are given) with the straight run's.
void expect_every_step_equal(Session& session, const std::vector<uint64_t>& hashes, const std::string& what,
                             const std::vector<uint64_t>& runs = {}) {
  ASSERT_EQ(session.latest() + 1, static_cast<int64_t>(hashes.size())) << what;
  for (int64_t t = 0; t <= session.latest(); ++t) {
    ASSERT_TRUE(session.seek(t));
    ASSERT_EQ(session.hash().whole(), hashes[size_t(t)]) << what << ": step " << t;
    if (!runs.empty()) {
      ASSERT_EQ(session.hash().run, runs[size_t(t)]) << what << ": run hash at step " << t;
    }
  }
}

TEST(Session, SeekingBackKeepsTheFutureAndResumingEqualsTheStraightRun) {
  const auto model = gossip_model({LatticeKind::Cubic, {6, 5, 4}}, kWatches);
  const Trail straight = straight_run(*model, 1, 60);
  ASSERT_EQ(straight.hashes.size(), 60u);
  for (size_t w = 0; w < 3; ++w) EXPECT_FALSE(straight.matches[w].empty()) << "watch " << w << " should match";

  StaticLatticeWorld world;
  Session run(*model, world, {.threads = 1});
  run.run_until(45);
  ASSERT_TRUE(run.seek(30));
  EXPECT_EQ(run.current(), 30);
  EXPECT_EQ(run.latest(), 44) << "looking at the past loses no future";
  EXPECT_EQ(run.hash().whole(), straight.hashes[30]);
  bool later = false;
  for (uint32_t w = 0; w < 3; ++w)
    for (int64_t d : run.matches(w).detected) later |= d > 30;
  EXPECT_TRUE(later) << "matches found after step 30 are kept";
  // On from step 30: steps 31..44 are revisited, 45..59 simulated.
  std::vector<int64_t> simulated;
  run.run_until(60, [&](const State&, const StepOutput& out) { simulated.push_back(out.step); });
  EXPECT_EQ(simulated.front(), 45);
  EXPECT_EQ(simulated.back(), 59);
  EXPECT_EQ(test::flat_matches(run), straight.matches);
  for (uint32_t w = 0; w < 3; ++w) EXPECT_EQ(run.match_count(w), straight.matches[w].size() / (w == 2 ? 3 : 4));
  expect_every_step_equal(run, straight.hashes, "after seeking back and forth");
  ASSERT_TRUE(run.seek(-1));
  EXPECT_EQ(run.state().step, 0) << "before step 0";
  EXPECT_FALSE(run.seek(60)) << "beyond the latest step";
}

TEST(Session, KeyframesThinToTheBudgetAndEveryStepIsStillReached) {
  const auto model = gossip_model({LatticeKind::Hex2d, {7, 6, 1}}, kWatches);
  const Trail straight = straight_run(*model, 1, 300);
  StaticLatticeWorld world;
  Session one(*model, world, {.threads = 2});
  const size_t budget = one.history_bytes() * 12;  // a dozen keyframes
  Session run(*model, world, {.threads = 2, .history_bytes = budget});
  run.run_until(300);
  EXPECT_GT(run.keyframe_interval(), 4) << "the interval grows with the history";
  EXPECT_LE(run.history_bytes(), budget);
  EXPECT_GE(run.keyframes(), 2u);
  // Backwards, so that each seek restores a keyframe rather than stepping on from the last one.
  for (int64_t t = 299; t >= 0; t -= 7) {
    ASSERT_TRUE(run.seek(t));
    ASSERT_EQ(run.hash().whole(), straight.hashes[size_t(t)]) << "step " << t;
  }
}

// A budget smaller than one keyframe: keyframe 0 alone, no copy kept of any other (nor as storage
// for the next), and every step still reached from it.
TEST(Session, ABudgetBelowOneKeyframeHoldsKeyframeZeroAlone) {
  const auto model = gossip_model({LatticeKind::Hex2d, {7, 6, 1}}, kWatches);
  const Trail straight = straight_run(*model, 1, 100);
  StaticLatticeWorld world;
  const size_t keyframe_zero = Session(*model, world, {.threads = 1, .history_bytes = 1}).history_bytes();
  Session run(*model, world, {.threads = 1, .history_bytes = 1});
  run.run_until(100);
  EXPECT_EQ(run.keyframes(), 1u);
  EXPECT_EQ(run.history_bytes(), keyframe_zero);
  EXPECT_GE(run.keyframe_interval(), 100);
  for (int64_t t : {99, 57, 3}) {
    ASSERT_TRUE(run.seek(t));
    ASSERT_EQ(run.hash().whole(), straight.hashes[size_t(t)]) << "step " << t;
  }
}

TEST(Session, WithoutHistoryOnlyTheLatestStepIsThere) {
  const auto model = gossip_model({LatticeKind::Ring, {10, 1, 1}}, {});
  StaticLatticeWorld world;
  Session run(*model, world, {.threads = 1, .history_bytes = 0});
  run.run_until(12);
  EXPECT_EQ(run.keyframes(), 0u);
  EXPECT_FALSE(run.seek(5));
  EXPECT_TRUE(run.seek(11));
  EXPECT_FALSE(run.set_watch({test_programs::compile("modules(a); a.v = 1")}));
  EXPECT_NE(run.record(std::cout), "");
}

// A watch stopped at its live budget: seen from before the stop, the state is not stopped, and
// on from there the run stops at the same step with the same hashes as the straight run.
TEST(Session, BudgetStopIsPartOfTheHistory) {
  // `count` grows by about one a step, so PatternMatchers pile up only after step 20 or so.
  const std::string text = "modules(a b c); (a.count > 30) and (b.count > 30) and (c.mix > b.mix)";
  auto model = gossip_model({LatticeKind::Cubic, {6, 5, 4}},
                            {{text, watch::Algorithm::Distributed}, {text, watch::Algorithm::Centralized}});
  for (HostedWatchpoint& h : model->watches) h.options.live_budget = 400;
  std::vector<uint64_t> first;  // the 1-thread run's hashes: the stop never depends on threads
  for (unsigned threads : {1u, 2u, 3u}) {
    const Trail straight = straight_run(*model, threads, 40);
    if (first.empty()) first = straight.hashes;
    EXPECT_EQ(straight.hashes, first) << threads << " threads";

    StaticLatticeWorld world;
    Session run(*model, world, {.threads = threads});
    run.run_until(40);
    for (uint32_t w : {0u, 1u}) {
      ASSERT_TRUE(run.stats(w).stopped) << "watch " << w << " should hit its budget";
      EXPECT_GE(run.stats(w).steps.size(), 20u) << "late, not at once: " << run.stats(w).stop_reason;
    }
    EXPECT_FALSE(run.matches(0).t.empty()) << "matches before the stop are kept";
    for (int64_t back : {19, 12, 2}) {
      ASSERT_TRUE(run.seek(back));
      EXPECT_FALSE(run.state().watches[0].stopped) << "at step " << back;
      EXPECT_EQ(run.hash().whole(), first[size_t(back)]);
    }
    expect_every_step_equal(run, first, std::to_string(threads) + " threads");
    EXPECT_EQ(test::flat_matches(run), straight.matches);
  }
}

TEST(Session, ThreadCountNeverChangesResults) {
  const auto model = gossip_model({LatticeKind::Cubic, {7, 6, 5}}, kWatches, 42);
  const Trail one = straight_run(*model, 1, 40);
  for (unsigned threads : {2u, 3u, 8u}) {
    const Trail many = straight_run(*model, threads, 40);
    EXPECT_EQ(many.hashes, one.hashes) << threads << " threads";
    EXPECT_EQ(many.runs, one.runs) << threads << " threads";
    EXPECT_EQ(many.matches, one.matches) << threads << " threads";
  }
}

// The run hash covers the history (issue 62, 10): a variable set and set back leaves the state of
// a run that never touched it, hash for hash, but not its run hash; a run resumed after a seek
// back chains the same run hash as one that never went back, on any thread count.
TEST(Session, RunHashCoversTheHistoryAndSurvivesSeeks) {
  std::vector<std::unique_ptr<const HostProgram>> programs;
  programs.push_back(std::make_unique<test_programs::SendsToStranger>(std::vector<ModuleId>{}));  // keeps `s`
  const auto model = std::get<std::unique_ptr<Model>>(
      build_model(make_lattice({LatticeKind::Line, {6, 1, 1}}), std::move(programs), {}, 1));
  const std::vector<Intervention> set_and_back{
      {.kind = Intervention::Kind::Set, .at = 2, .module = 3, .column = 0, .value = 5},
      {.kind = Intervention::Kind::Set, .at = 4, .module = 3, .column = 0, .value = 0}};
  const Trail untouched = straight_run(*model, 1, 8), touched = straight_run(*model, 1, 8, set_and_back);
  EXPECT_EQ(touched.hashes.back(), untouched.hashes.back()) << "the same final state";
  EXPECT_NE(touched.hashes[3], untouched.hashes[3]);
  EXPECT_EQ(touched.runs[1], untouched.runs[1]) << "the same history up to step 1";
  EXPECT_NE(touched.runs.back(), untouched.runs.back()) << "different histories";

  const auto gossip = gossip_model({LatticeKind::Cubic, {5, 4, 3}}, kWatches);
  const Trail straight = straight_run(*gossip, 1, 30);
  for (unsigned threads : {1u, 3u}) {
    StaticLatticeWorld world;
    Session run(*gossip, world, {.threads = threads});
    run.run_until(12);
    ASSERT_TRUE(run.seek(4));
    EXPECT_EQ(run.hash().run, straight.runs[4]);
    run.run_until(30);
    EXPECT_EQ(run.hash().run, straight.runs.back()) << threads << " threads: resumed after a seek back";
    expect_every_step_equal(run, straight.hashes, std::to_string(threads) + " threads", straight.runs);
  }
}

TEST(Session, SeedChangesTheRun) {
  const auto a = gossip_model({LatticeKind::Line, {20, 1, 1}}, {}, 1);
  const auto b = gossip_model({LatticeKind::Line, {20, 1, 1}}, {}, 2);
  EXPECT_NE(straight_run(*a, 1, 10).hashes, straight_run(*b, 1, 10).hashes);
  EXPECT_EQ(straight_run(*a, 1, 10).hashes, straight_run(*a, 1, 10).hashes);
}

// The cursor stops on a pause match's own step once every watchpoint has decided it, and a run
// from there goes on to the next one.
TEST(Session, PauseStopsTheCursorAtTheMatchStep) {
  auto model = gossip_model({LatticeKind::Square2d, {5, 5, 1}},
                            {{"modules(a b); (a.v = 1) and (b.v = 1)", watch::Algorithm::Distributed},
                             {"modules(a b c); (a.v = 2) and (b.v = 2) and (c.v = 2)", watch::Algorithm::Distributed}});
  model->watches[0].action = MatchAction::Pause;
  StaticLatticeWorld world;
  Session run(*model, world, {.threads = 1});
  const auto pause = run.run_until(50);
  ASSERT_TRUE(pause);
  EXPECT_EQ(pause->t, pause->detected - 1) << "two slots: found one step after it started";
  EXPECT_EQ(run.current(), pause->t);
  EXPECT_EQ(run.latest(), pause->t + 2) << "ahead until the three-slot watch decided the step too";
  EXPECT_GE(run.decided(), pause->t);
  EXPECT_EQ(pause->group.size(), 2u);
  const auto [first, last] = run.matches(0).at(pause->t);
  EXPECT_EQ(pause->matches, last - first);
  const auto next = run.run_until(50);
  ASSERT_TRUE(next);
  EXPECT_GT(next->t, pause->t);
  EXPECT_EQ(run.current(), next->t);
}

// `run --to-match W`: each run stops at the next step with a match of W, then of a pause watchpoint
// too; together they visit exactly the steps with matches that a straight run found.
TEST(Session, RunToMatchStopsAtEveryStepWithAMatchOfThatWatchpoint) {
  const std::vector<std::pair<std::string, watch::Algorithm>> watches{
      {"modules(a b); (a.v = 1) and (b.v = 1)", watch::Algorithm::Distributed},
      {"modules(a b c); (a.v = 2) and (b.v = 2) and (c.v = 2)", watch::Algorithm::Centralized}};
  auto straight_model = gossip_model({LatticeKind::Square2d, {5, 5, 1}}, watches);
  StaticLatticeWorld straight_world;
  Session straight(*straight_model, straight_world, {.threads = 1});
  straight.run_until(60);
  auto steps_of = [](const MatchList& list) {
    std::set<int64_t> steps(list.t.begin(), list.t.end());
    return steps;
  };
  const std::set<int64_t> matched = steps_of(straight.matches(1)), paused = steps_of(straight.matches(0));
  ASSERT_GE(matched.size(), 2u) << "the case must have several steps to stop at";

  for (const bool with_pause : {false, true}) {
    auto model = gossip_model({LatticeKind::Square2d, {5, 5, 1}}, watches);
    if (with_pause) model->watches[0].action = MatchAction::Pause;
    StaticLatticeWorld world;
    Session run(*model, world, {.threads = 2});
    std::set<int64_t> expected = matched;
    if (with_pause) expected.insert(paused.begin(), paused.end());
    std::vector<int64_t> stops;
    while (const auto stop = run.run_until(60, {}, {}, 1u)) {
      EXPECT_EQ(run.current(), stop->t);
      EXPECT_EQ(stop->asked, stop->watch == 1u);
      EXPECT_EQ(stop->asked, !with_pause || !paused.count(stop->t)) << "a pause of an earlier watchpoint comes first";
      stops.push_back(stop->t);
    }
    EXPECT_EQ(run.current(), 59);
    EXPECT_EQ(stops, std::vector<int64_t>(expected.begin(), expected.end())) << "with_pause " << with_pause;
  }
}

// `action W ...` changes what W does from now on: no pause after a pause watchpoint becomes a
// log one, its matches kept; one that counts keeps the number of every match, not the list.
TEST(Session, ChangingAWatchpointsActionReevaluatesNothing) {
  const std::vector<std::pair<std::string, watch::Algorithm>> watches{
      {"modules(a b); (a.v = 1) and (b.v = 1)", watch::Algorithm::Distributed}};
  auto straight_model = gossip_model({LatticeKind::Square2d, {5, 5, 1}}, watches);
  StaticLatticeWorld straight_world;
  Session straight(*straight_model, straight_world, {.threads = 1});
  straight.run_until(60);
  const MatchList& all = straight.matches(0);
  ASSERT_GE(std::set<int64_t>(all.t.begin(), all.t.end()).size(), 3u);

  auto model = gossip_model({LatticeKind::Square2d, {5, 5, 1}}, watches);
  model->watches[0].action = MatchAction::Pause;
  StaticLatticeWorld world;
  Session run(*model, world, {.threads = 1});
  const auto pause = run.run_until(60);
  ASSERT_TRUE(pause);
  EXPECT_EQ(pause->t, all.t.front());
  const uint64_t matches_then = run.match_count(0);
  run.set_action(0, MatchAction::Log);
  EXPECT_FALSE(run.run_until(60)) << "a log watchpoint does not pause";
  EXPECT_EQ(run.current(), 59);
  EXPECT_EQ(run.matches(0).t, all.t) << "every match kept, none found twice";
  ASSERT_TRUE(run.seek(pause->t - 1));
  EXPECT_FALSE(run.run_until(60)) << "nor on steps revisited";
  run.set_action(0, MatchAction::Pause);
  ASSERT_TRUE(run.seek(pause->t - 1));
  const auto again = run.run_until(60);
  ASSERT_TRUE(again) << "pausing again on the steps already simulated";
  EXPECT_EQ(again->t, pause->t);
  EXPECT_GT(matches_then, 0u);

  // Switched to count before the rest is simulated: counted, not listed.
  auto counted_model = gossip_model({LatticeKind::Square2d, {5, 5, 1}}, watches);
  StaticLatticeWorld counted_world;
  Session counted(*counted_model, counted_world, {.threads = 1});
  counted.run_until(pause->t + 1);
  const size_t listed = counted.matches(0).size();
  counted.set_action(0, MatchAction::Count);
  counted.run_until(60);
  EXPECT_EQ(counted.matches(0).size(), listed);
  EXPECT_EQ(counted.match_count(0), all.size());
}

// A `count` watchpoint keeps how many matches each step had, not the groups: step by step what a
// `log` twin lists, through a branch that drops the future and the drain at the run's end.
TEST(Session, ACountWatchpointKeepsTheNumberOfEachStep) {
  const auto logged_model = gossip_model({LatticeKind::Cubic, {5, 4, 3}}, kWatches);
  const auto counted_model = gossip_model({LatticeKind::Cubic, {5, 4, 3}}, kWatches);
  for (HostedWatchpoint& h : counted_model->watches) h.action = MatchAction::Count;
  StaticLatticeWorld logged_world, counted_world;
  Session logged(*logged_model, logged_world, {.threads = 1}), counted(*counted_model, counted_world, {.threads = 2});
  for (Session* run : {&logged, &counted}) {
    run->run_until(45);
    ASSERT_TRUE(run->seek(25));
    const Intervention set{
        .kind = Intervention::Kind::Set, .module = 7, .column = logged_model->column("count"), .value = 100};
    ASSERT_EQ(run->intervene(set), "");
    run->run_until(50);
    run->drain();
  }
  for (uint32_t w = 0; w < kWatches.size(); ++w) {
    SCOPED_TRACE(w);
    const MatchList& list = logged.matches(w);
    ASSERT_GT(list.size(), 0u);
    EXPECT_EQ(counted.matches(w).size(), 0u) << "no group kept";
    uint64_t total = 0;
    for (int64_t t = 0; t < 50; ++t) {
      const auto [first, last] = list.at(t);
      EXPECT_EQ(counted.matches(w).counted_at(t), last - first) << "step " << t;
      total += counted.matches(w).counted_at(t);
    }
    EXPECT_EQ(total, counted.match_count(w));
    EXPECT_EQ(counted.match_counts(w, 0, 49), logged.match_counts(w, 0, 49));
  }
}

// An intervention cuts the future: the branch equals a straight run with the same intervention
// scheduled as an event, and earlier interventions of the dropped future are gone.
TEST(Session, InterventionStartsABranchEqualToTheScheduledRun) {
  const auto model = gossip_model({LatticeKind::Cubic, {5, 4, 3}}, kWatches);
  StaticLatticeWorld world;
  Session run(*model, world, {.threads = 2});
  run.run_until(40);
  ASSERT_TRUE(run.seek(30));
  ASSERT_EQ(
      run.intervene({.kind = Intervention::Kind::Set, .module = 7, .column = model->column("count"), .value = 100}),
      "");
  EXPECT_EQ(run.latest(), 32) << "the future is dropped, and step 30 decided again (lag 2)";
  ASSERT_TRUE(run.seek(20));
  ASSERT_EQ(run.intervene({.kind = Intervention::Kind::Remove, .module = 3}), "");
  ASSERT_EQ(run.interventions().size(), 1u) << "the set at step 31 belonged to the dropped future";
  EXPECT_EQ(run.interventions()[0].at, 21);
  run.run_until(40);
  EXPECT_FALSE(run.seen_present()[3]) << "removed";
  EXPECT_TRUE(run.seen_graph().neighbors(3).empty());
  for (ModuleId n = 0; n < model->module_count(); ++n) EXPECT_FALSE(run.seen_graph().adjacent(n, 3));

  const Trail straight = straight_run(*model, 1, 40, run.interventions());
  expect_every_step_equal(run, straight.hashes, "branch");
  EXPECT_EQ(test::flat_matches(run), straight.matches);
  const Trail untouched = straight_run(*model, 1, 40);
  EXPECT_EQ(straight.hashes[20], untouched.hashes[20]);
  EXPECT_NE(straight.hashes[21], untouched.hashes[21]);

  EXPECT_NE(run.intervene({.kind = Intervention::Kind::Push, .module = 1}), "") << "no bodies to push";
  EXPECT_NE(run.intervene({.kind = Intervention::Kind::Set, .module = 9999, .column = 0}), "");
}

HostedWatchpoint hosted(const std::string& name, const std::string& text, watch::Algorithm algorithm) {
  auto compiled = watch::compile_watchpoint(name, watch::SourceText("<test>", text));
  return {std::get<watch::Watchpoint>(std::move(compiled)), algorithm, MatchAction::Log, {}};
}

// A watchpoint added late finds exactly what it would have found from step 0, and replacing or
// removing one leaves the others as they were.
TEST(Session, RetroactiveWatchpointEqualsOneThatWatchedFromTheStart) {
  for (const auto& [text, algorithm] : kWatches) {
    const auto fresh = gossip_model({LatticeKind::Cubic, {6, 5, 4}}, {{text, algorithm}});
    const Trail expected = straight_run(*fresh, 1, 50);
    ASSERT_FALSE(expected.matches[0].empty()) << text;

    const auto model = gossip_model({LatticeKind::Cubic, {6, 5, 4}}, {});
    StaticLatticeWorld world;
    Session run(*model, world, {.threads = 2, .history_bytes = 100 << 10});
    run.run_until(35);
    ASSERT_TRUE(run.seek(12));
    const auto w = run.set_watch(hosted("late", text, algorithm));
    ASSERT_EQ(w, 0u);
    EXPECT_EQ(run.current(), 12) << "adding a watchpoint does not move the cursor";
    run.run_until(50);
    EXPECT_EQ(test::flat_matches(run), expected.matches) << text;
    expect_every_step_equal(run, expected.hashes, text);
  }
}

TEST(Session, ReplacingAndRemovingWatchpoints) {
  const auto model = gossip_model({LatticeKind::Cubic, {5, 5, 3}}, kWatches);
  const Trail all = straight_run(*model, 1, 30);
  // The second watchpoint ("w", like all three here), named to be replaced by the third's text.
  model->watches[1].watchpoint.name = "second";
  StaticLatticeWorld world;
  Session run(*model, world, {.threads = 1});
  run.run_until(30);
  ASSERT_EQ(run.set_watch(hosted("second", kWatches[2].first, kWatches[2].second)), 1u);
  const auto flat = test::flat_matches(run);
  EXPECT_EQ(flat[0], all.matches[0]);
  EXPECT_EQ(flat[1], all.matches[2]);
  EXPECT_EQ(flat[2], all.matches[2]);
  EXPECT_TRUE(run.remove_watch("second"));
  EXPECT_FALSE(run.remove_watch("second"));
  ASSERT_EQ(run.watches().size(), 2u);
  EXPECT_EQ(test::flat_matches(run), (std::vector<std::vector<int64_t>>{all.matches[0], all.matches[2]}));
  // The session's states hold exactly the watchpoints left: they hash as a straight run of those.
  const auto two = gossip_model({LatticeKind::Cubic, {5, 5, 3}}, {kWatches[0], kWatches[2]});
  expect_every_step_equal(run, straight_run(*two, 1, 30).hashes, "two left");
}

// Random walks of every operation against a straight run with the walk's interventions
// scheduled: equal hashes at every step and equal matches.
TEST(Session, RandomWalksEqualTheStraightRunWithTheSameEvents) {
  const std::vector<std::string> texts{kWatches[0].first, kWatches[2].first,
                                       "modules(a b); (a.count > 20) and (b.count > a.count)"};
  for (unsigned threads : {1u, 2u}) {
    for (uint32_t seed = 1; seed <= 4; ++seed) {
      std::mt19937 rng(seed * 7919 + threads);
      auto pick = [&](int64_t n) { return static_cast<int64_t>(rng() % static_cast<uint64_t>(n)); };
      const LatticeSpec spec{LatticeKind::Cubic, {5, 4, 3}};
      const auto model = gossip_model(spec, {});
      StaticLatticeWorld world;
      Session run(*model, world, {.threads = threads, .end = 60, .history_bytes = size_t(60 + pick(200)) << 10});
      std::string log;
      for (int op = 0; op < 25; ++op) {
        const int64_t kind = pick(8);
        if (kind <= 1) {
          run.run_until(std::min<int64_t>(60, run.current() + 2 + pick(12)));
          log += " run>" + std::to_string(run.current());
        } else if (kind == 2 && run.latest() >= 0) {
          run.seek(pick(run.latest() + 1));
          log += " seek" + std::to_string(run.current());
        } else if (kind == 3) {
          const ModuleId m = static_cast<ModuleId>(pick(model->module_count()));
          const int column = static_cast<int>(pick(3));
          // On a module already gone, refused as a remove is.
          const std::string refused =
              run.intervene({.kind = Intervention::Kind::Set, .module = m, .column = column, .value = pick(40)});
          ASSERT_TRUE(refused.empty() || refused.find("is already gone") != std::string::npos) << refused;
          log += (refused.empty() ? " set@" : " gone@") + std::to_string(run.current());
        } else if (kind == 4) {
          // A module already gone is refused, and no event is recorded for it.
          const std::string refused = run.intervene({.kind = Intervention::Kind::Remove, .module = ModuleId(pick(60))});
          ASSERT_TRUE(refused.empty() || refused.find("is already gone") != std::string::npos) << refused;
          log += (refused.empty() ? " remove@" : " gone@") + std::to_string(run.current());
        } else if (kind == 5 || kind == 6) {
          const size_t which = static_cast<size_t>(pick(3));
          const auto algorithm = pick(2) ? watch::Algorithm::Centralized : watch::Algorithm::Distributed;
          ASSERT_TRUE(run.set_watch(hosted("w" + std::to_string(which), texts[which], algorithm)));
          log += " watch" + std::to_string(which);
        } else {
          run.remove_watch("w" + std::to_string(pick(3)));
          log += " unwatch";
        }
      }
      run.run_until(60);
      SCOPED_TRACE("threads " + std::to_string(threads) + ", walk" + log);

      std::vector<HostedWatchpoint> watches;
      for (uint32_t w = 0; w < run.watches().size(); ++w) {
        const HostedWatchpoint& h = run.watches()[w].hosted;
        watches.push_back(hosted(h.watchpoint.name, h.watchpoint.source->text(), h.algorithm));
      }
      std::vector<std::unique_ptr<const HostProgram>> programs;
      programs.push_back(std::make_unique<test_programs::Gossip>());
      auto again = std::get<std::unique_ptr<Model>>(build_model(make_lattice(spec), std::move(programs), watches, 1));
      const Trail straight = straight_run(*again, threads, 60, run.interventions());
      EXPECT_EQ(test::flat_matches(run), straight.matches);
      expect_every_step_equal(run, straight.hashes, "walk");
    }
  }
}

// A cancelled operation changes nothing; a cancel during a run leaves it at a step it reached.
TEST(Session, CancelledOperationsLeaveTheSessionAsItWas) {
  const auto model = gossip_model({LatticeKind::Cubic, {5, 4, 3}}, {kWatches[0]});
  const Trail straight = straight_run(*model, 1, 40);
  StaticLatticeWorld world;
  Session run(*model, world, {.threads = 1, .history_bytes = 30 << 10});
  run.run_until(40);
  std::stop_source stop;
  int64_t calls = 0;
  const Control cancel_soon{stop.get_token(), [&](int64_t done, int64_t) {
                              if (++calls == 3 || done > 5) stop.request_stop();
                            }};
  EXPECT_FALSE(run.set_watch(hosted("late", kWatches[1].first, kWatches[1].second), cancel_soon));
  EXPECT_EQ(run.watches().size(), 1u);
  EXPECT_EQ(run.current(), 39);

  std::stop_source stop2;
  calls = 0;
  const Control cancel_seek{stop2.get_token(), [&](int64_t, int64_t) {
                              if (++calls == 2) stop2.request_stop();
                            }};
  ASSERT_GT(run.keyframe_interval(), 2);
  EXPECT_FALSE(run.seek(run.keyframe_interval() + 2, cancel_seek));
  EXPECT_EQ(run.current(), 39);
  expect_every_step_equal(run, straight.hashes, "after cancels");
  EXPECT_EQ(test::flat_matches(run), straight.matches);
}

TEST(Session, QueriesForViews) {
  const auto model = gossip_model({LatticeKind::Cubic, {5, 4, 3}}, {kWatches[0]});
  StaticLatticeWorld world;
  Session run(*model, world, {.threads = 1, .history_bytes = 30 << 10});
  std::vector<int64_t> mix_of_7, all_of_7;
  const size_t v = model->variable_count();
  run.run_until(50, [&](const State& s, const StepOutput&) {
    mix_of_7.push_back(s.values[7 * v + 1]);
    all_of_7.insert(all_of_7.end(), s.values.begin() + 7 * v, s.values.begin() + 8 * v);
  });
  const auto series = run.series(7, model->column("mix"), 10, 45);
  ASSERT_TRUE(series);
  EXPECT_EQ(*series, std::vector<int64_t>(mix_of_7.begin() + 10, mix_of_7.begin() + 46));
  // Every variable at once, as the window's inspector reads them: rows of the step's values.
  const auto rows = run.module_series(7, 0, 49);
  ASSERT_TRUE(rows);
  EXPECT_EQ(*rows, all_of_7);

  const MatchList& list = run.matches(0);
  ASSERT_FALSE(list.t.empty());
  const std::vector<uint64_t> counts = run.match_counts(0, 0, 49);
  uint64_t total = 0;
  for (int64_t t = 0; t < 50; ++t) {
    const auto [first, last] = list.at(t);
    EXPECT_EQ(counts[size_t(t)], last - first);
    for (size_t i = first; i < last; ++i) EXPECT_EQ(list.t[i], t);
    total += counts[size_t(t)];
  }
  EXPECT_EQ(total, list.size());
  EXPECT_EQ(run.decided(0), 49 - model->watches[0].lag());
}

TEST(Session, RecordedTraceListsTheInterventionsAndReplaysTheFrames) {
  const auto model = gossip_model({LatticeKind::Ring, {8, 1, 1}}, {});
  StaticLatticeWorld world;
  Session run(*model, world, {.threads = 1});
  run.run_until(6);
  ASSERT_EQ(run.intervene({.kind = Intervention::Kind::Set, .module = 2, .column = 0, .value = 9}), "");
  run.run_until(10);
  std::ostringstream out;
  ASSERT_EQ(run.record(out), "");
  const std::string text = out.str();
  EXPECT_EQ(text.substr(0, text.find('\n')),
            "{\"wptrace\":1,\"interventions\":[{\"at\":6,\"module\":2,\"set\":{\"v\":9}}]}");
  auto read = read_trace_text("t.jsonl", text);
  ASSERT_TRUE(std::holds_alternative<Trace>(read));
  EXPECT_EQ(std::get<Trace>(read).step_count(), 10);
}

}  // namespace
}  // namespace dw::sim
