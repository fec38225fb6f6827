// Token passing (scenarios/programs/token_ring.cpp) under the Fig. 3 watchpoint: the first match comes
// exactly where the injected bug puts it, and never without a bug.
#include <gtest/gtest.h>

#include "tests/scenarios/scenario_helpers.h"

namespace dw::scenarios {
namespace {

const char* kFig3 =
    "modules(a x b); neighbor(x b) and (x.token = 1) and (((a.last.token = 1) and (b.last.token = 1)) or "
    "((a.last.token = 0) and (b.last.token = 0)))";

// The Fig. 3 watchpoint read centrally, or by the modules over simultaneous states (docs/design.md §4a),
// or by the paper's distributed algorithm over consistent states.
const char* kCentralized = "algorithm = \"centralized\"";
const char* kSimultaneous = "algorithm = \"distributed\"\nstates = \"simultaneous\"";
const char* kConsistent = "algorithm = \"distributed\"";

std::string scenario(uint32_t n, const std::string& bug, const char* reading = kCentralized) {
  return "[lattice]\nkind = \"ring\"\nsize = [" + std::to_string(n) + "]\n[[program]]\nname = \"token_ring\"\n" + bug +
         "\n[[watch]]\nname = \"fig3\"\n" + reading + "\naction = \"log\"\ntext = \"" + kFig3 + "\"\n";
}

// The matches of a run of `steps` steps, drained at the end: (t, slots) in order.
std::vector<std::pair<int64_t, std::vector<sim::ModuleId>>> run_matches(const std::string& text, int64_t steps) {
  Scenario s = test::load(text);
  sim::Session run(*s.model, *s.world, {.threads = 1});
  run.run_until(steps);
  run.drain();
  const sim::MatchList& m = run.matches(0);
  std::vector<std::pair<int64_t, std::vector<sim::ModuleId>>> out;
  for (size_t i = 0; i < m.size(); ++i) out.push_back({m.t[i], {m.slots.begin() + 3 * i, m.slots.begin() + 3 * i + 3}});
  std::sort(out.begin(), out.end());
  return out;
}

TEST(TokenRing, ExactlyOneModuleHoldsTheTokenEveryStep) {
  Scenario s = test::load(scenario(9, ""));
  test::History token;
  sim::Session run(*s.model, *s.world, {.threads = 1});
  run.run_until(50, test::record(*s.model, "token", token));
  for (int64_t t = 0; t < 50; ++t) {
    int holders = 0;
    for (sim::ModuleId m = 0; m < 9; ++m) holders += token(t, m) != 0;
    EXPECT_EQ(holders, 1) << "step " << t;
    EXPECT_EQ(token(t, sim::ModuleId(t % 9)), 1) << "the token moves one module per step";
  }
}

TEST(TokenRing, CorrectRingNeverMatches) {
  for (uint32_t n : {3u, 4u, 5u, 16u, 31u}) {
    Scenario s = test::load(scenario(n, ""));
    sim::Session run(*s.model, *s.world, {.threads = 1});
    run.run_until(200);
    EXPECT_EQ(run.match_count(0), 0u) << n << " modules";
  }
}

TEST(TokenRing, DuplicatedTokenMatchesTheStepAfterAtTheHolder) {
  for (auto [n, at] : {std::pair{16u, 40}, {16u, 5}, {7u, 30}, {4u, 9}}) {
    SCOPED_TRACE(std::to_string(n) + " modules, duplicate_at " + std::to_string(at));
    Scenario s = test::load(scenario(n, "duplicate_at = " + std::to_string(at)));
    sim::Session run(*s.model, *s.world, {.threads = 1});
    run.run_until(at + 60);
    const sim::MatchList& m = run.matches(0);
    ASSERT_GT(m.size(), 0u);
    EXPECT_EQ(m.t[0], at + 1);
    const sim::ModuleId holder = sim::ModuleId(at % int(n));
    EXPECT_EQ(m.slots[1], holder) << "x is the module that kept the token";
    // Both orders of its two neighbours, and nothing else ever.
    EXPECT_EQ(m.size(), 2u);
  }
}

TEST(TokenRing, LostTokenMatchesWhenTheMasterRegeneratesIt) {
  for (auto [n, at] : {std::pair{16u, 40}, {16u, 47}, {5u, 12}}) {
    SCOPED_TRACE(std::to_string(n) + " modules, lose_at " + std::to_string(at));
    Scenario s = test::load(scenario(n, "lose_at = " + std::to_string(at)));
    sim::Session run(*s.model, *s.world, {.threads = 1});
    run.run_until(at + 3 * int(n));
    const sim::MatchList& m = run.matches(0);
    ASSERT_GT(m.size(), 0u);
    // The master last had the token at the last multiple of n; it waits n steps more, then one.
    const int64_t last_seen = at / int64_t(n) * int64_t(n);
    EXPECT_EQ(m.t[0], last_seen + n + 1);
    EXPECT_EQ(m.slots[1], 0u) << "the master regenerates";
  }
}

// The modules find exactly what the centralized reading finds: the duplicated and the lost
// tokens, and nothing on a correct ring, where the paper's consistent reading (b.last read a step
// after a's) matches a correct token at every step.
TEST(TokenRing, SimultaneousDistributedReadingFindsExactlyTheCentralizedMatches) {
  for (const std::string bug : {"", "duplicate_at = 40", "duplicate_at = 5", "lose_at = 40", "lose_at = 47"}) {
    SCOPED_TRACE(bug);
    const auto central = run_matches(scenario(16, bug, kCentralized), 120);
    const auto distributed = run_matches(scenario(16, bug, kSimultaneous), 120);
    EXPECT_EQ(distributed, central);
    EXPECT_EQ(central.empty(), bug.empty());
  }
  EXPECT_GT(run_matches(scenario(16, "", kConsistent), 120).size(), 100u);
}

TEST(TokenRing, ShippedDistributedScenarioPausesAtStep41) {
  auto loaded = load_scenario(std::string(DWATCH_SCENARIOS_DIR) + "/token_ring_distributed.toml");
  ASSERT_TRUE(std::holds_alternative<Scenario>(loaded));
  Scenario& s = std::get<Scenario>(loaded);
  ASSERT_TRUE(watch::simultaneous(s.model->watches[0].algorithm, s.model->watches[0].options));
  sim::Session run(*s.model, *s.world, {.threads = s.threads});
  const auto pause = run.run_until(s.steps);
  ASSERT_TRUE(pause);
  EXPECT_EQ(pause->t, 41);
  EXPECT_EQ(pause->detected, 41 + 2) << "E+ = 0, and a chain of 3 takes L = 2 hops";
  EXPECT_EQ(pause->group[1], 40u % 16u);
}

TEST(TokenRing, ShippedScenarioPausesAtStep41) {
  auto loaded = load_scenario(std::string(DWATCH_SCENARIOS_DIR) + "/token_ring.toml");
  ASSERT_TRUE(std::holds_alternative<Scenario>(loaded));
  Scenario& s = std::get<Scenario>(loaded);
  sim::Session run(*s.model, *s.world, {.threads = s.threads});
  const auto pause = run.run_until(s.steps);
  ASSERT_TRUE(pause);
  EXPECT_EQ(pause->t, 41);
  EXPECT_EQ(pause->group[1], 40u % 16u);
}

}  // namespace
}  // namespace dw::scenarios
