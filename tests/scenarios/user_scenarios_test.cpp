// The scenarios issue 61's users asked for (docs/design.md §4c), each with a planted bug its
// watchpoint catches: the ring's one token (zero slots, `all`), a leader since the round it won
// (`since`), a parent that flaps (`times`), every cluster one head (`component`). Each scenario's
// matches, in both readings, equal what its invariant says of the states the run went through.
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <set>

#include "scenarios/scenario.h"
#include "sim/session.h"
#include "sim/state.h"
#include "sim/watch_hosting.h"

namespace dw::scenarios {
namespace {

using Rows = std::set<std::pair<int64_t, std::vector<watch::ModuleId>>>;

Scenario load(const std::string& path, watch::Algorithm algorithm) {
  ScenarioOverrides overrides;
  overrides.algorithm = algorithm;
  auto loaded = load_scenario(path, overrides);
  if (auto* e = std::get_if<std::string>(&loaded)) ADD_FAILURE() << *e;
  return std::move(std::get<Scenario>(loaded));
}

// The scenario run to its end: its first watchpoint's matches, and each step's values
// ([t][module * variables + column]) and presence.
struct Ran {
  Rows matches;
  std::vector<std::vector<int64_t>> values;
  std::vector<std::vector<uint8_t>> present;
  size_t stride = 0;                 // variables a module
  std::map<std::string, size_t> at;  // variable -> column
  int64_t value(int64_t t, uint32_t m, const std::string& v) const { return values[size_t(t)][m * stride + at.at(v)]; }
};

Ran run(const std::string& name, watch::Algorithm algorithm) {
  Scenario s = load(std::string(DWATCH_SCENARIOS_DIR "/") + name, algorithm);
  sim::Session session(*s.model, *s.world, {.threads = 2, .end = s.steps});
  Ran ran;
  ran.stride = s.model->variable_count();
  for (const std::string& v : s.model->universe.variables) ran.at[v] = static_cast<size_t>(s.model->column(v));
  session.run_until(s.steps, [&](const sim::State& st, const sim::StepOutput&) {
    ran.values.push_back(st.values);
    ran.present.push_back(st.present);
  });
  session.drain();
  EXPECT_EQ(static_cast<int64_t>(ran.values.size()), s.steps);
  const sim::MatchList& list = session.matches(0);
  const size_t k = static_cast<size_t>(session.watches()[0].hosted.watchpoint.program.slot_count());
  for (size_t i = 0; i < list.size(); ++i)
    ran.matches.insert(
        {list.t[i], std::vector<watch::ModuleId>(list.slots.begin() + static_cast<ptrdiff_t>(i * k),
                                                 list.slots.begin() + static_cast<ptrdiff_t>(i * k + k))});
  return ran;
}

// The rows (t, {m}) of the one-slot matches `holds(t, m)` gives, t over the run.
Rows one_slot(const Ran& ran, uint32_t modules, const std::function<bool(int64_t, uint32_t)>& holds) {
  Rows rows;
  for (int64_t t = 0; t < static_cast<int64_t>(ran.values.size()); ++t)
    for (uint32_t m = 0; m < modules; ++m)
      if (holds(t, m)) rows.insert({t, {m}});
  return rows;
}

constexpr watch::Algorithm kBoth[] = {watch::Algorithm::Centralized, watch::Algorithm::Distributed};

TEST(UserScenarios, OneTokenRingMatchesEveryStepWithTwoTokensWithNoModule) {
  for (watch::Algorithm a : kBoth) {
    const Ran ran = run("one_token_ring.toml", a);
    Rows want;
    for (int64_t t = 0; t < static_cast<int64_t>(ran.values.size()); ++t) {
      int tokens = 0;
      for (uint32_t m = 0; m < 12; ++m) tokens += ran.present[size_t(t)][m] && ran.value(t, m, "token") == 1;
      if (tokens != 1) want.insert({t, {}});
    }
    EXPECT_EQ(ran.matches, want) << watch::algorithm_name(a);
    ASSERT_FALSE(want.empty());
    EXPECT_EQ(want.begin()->first, 21);  // the copy made at step 20 is held from step 21
  }
  // Over MPI ranks every rank decides it alike from every rank's values (tests/dist).
  const Scenario s = load(DWATCH_SCENARIOS_DIR "/one_token_ring.toml", watch::Algorithm::Distributed);
  EXPECT_EQ(sim::why_not_over_ranks(*s.model), "");
}

TEST(UserScenarios, LeaderSinceWonCatchesTheImpostorFromItsClaim) {
  for (watch::Algorithm a : kBoth) {
    const Ran ran = run("leader_since_won.toml", a);
    EXPECT_EQ(ran.value(20, 0, "won"), 1) << "module 0 won at step 20";
    EXPECT_EQ(ran.value(39, 0, "isLeader"), 1);
    EXPECT_EQ(ran.matches, one_slot(ran, 48, [](int64_t t, uint32_t m) { return m == 17 && t >= 30; }))
        << watch::algorithm_name(a);
  }
}

TEST(UserScenarios, ParentFlapMatchesMoreThanThreeChangesInTwentySteps) {
  for (watch::Algorithm a : kBoth) {
    const Ran ran = run("parent_flap.toml", a);
    auto changed = [&](int64_t s, uint32_t m) { return ran.value(s, m, "parent") != ran.value(s - 1, m, "parent"); };
    // times[20](a.parent != a.last.parent) > 3: j = 0..20, clipped at step 1 (a.last reads step 0).
    const Rows want = one_slot(ran, 64, [&](int64_t t, uint32_t m) {
      int changes = 0;
      for (int64_t j = 0; j <= 20 && t - j >= 1; ++j) changes += changed(t - j, m);
      return changes > 3;
    });
    EXPECT_EQ(ran.matches, want) << watch::algorithm_name(a);
    ASSERT_FALSE(want.empty());
    for (const auto& [t, ids] : want) EXPECT_EQ(ids, std::vector<watch::ModuleId>{27}) << "at step " << t;
  }
}

TEST(UserScenarios, ClusterHeadsMatchEveryModuleOfTheClusterWithTwoHeads) {
  for (watch::Algorithm a : kBoth) {
    const Ran ran = run("cluster_heads.toml", a);
    // Every module of module 22's cluster (x 6..7, y 0..2) from step 10 on.
    const Rows want = one_slot(ran, 64, [](int64_t t, uint32_t m) { return t >= 10 && m % 8 >= 6 && m / 8 <= 2; });
    EXPECT_EQ(ran.matches, want) << watch::algorithm_name(a);
    EXPECT_EQ(want.size(), 6u * 10u);
  }
}

}  // namespace
}  // namespace dw::scenarios
