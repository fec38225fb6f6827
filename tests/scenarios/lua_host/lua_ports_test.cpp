// Host programs in Lua (scenarios/lua_host/lua_program.h) beside their C++ twins: a port gives its
// twin's states bit for bit and the same matches, on any thread count, through rollback and in a
// Bullet world; docs/lua.md's gradient example finds every hop distance.
#include <gtest/gtest.h>

#include <filesystem>

#include "tests/scenarios/scenario_helpers.h"

namespace dw::scenarios {
namespace {

namespace fs = std::filesystem;

const fs::path kLua = fs::path(DWATCH_SCENARIOS_DIR) / "lua";

const char* kFig3 =
    "modules(a x b); neighbor(x b) and (x.token = 1) and (((a.last.token = 1) and (b.last.token = 1)) or "
    "((a.last.token = 0) and (b.last.token = 0)))";

// A 16-module ring running token_ring, built in or from scenarios/lua/token_ring.lua, under the
// Fig. 3 watchpoint.
Scenario ring(bool lua, const std::string& bug, unsigned threads = 1) {
  const std::string program =
      lua ? "[[program]]\nscript = \"token_ring.lua\"\n" : "[[program]]\nname = \"token_ring\"\n";
  const std::string text =
      "threads = " + std::to_string(threads) + "\n[lattice]\nkind = \"ring\"\nsize = [16]\n" + program + bug +
      "\n[[watch]]\nname = \"fig3\"\nalgorithm = \"centralized\"\naction = " + "\"log\"\ntext = \"" + kFig3 + "\"\n";
  auto loaded = load_scenario_text((kLua / "inline.toml").string(), text);
  if (auto* e = std::get_if<std::string>(&loaded)) ADD_FAILURE() << *e;
  return std::move(std::get<Scenario>(loaded));
}

TEST(LuaProgram, TokenRingPortGivesTheTwinsStateEveryStepAndTheSameMatches) {
  for (const std::string bug : {"", "duplicate_at = 40", "lose_at = 47"}) {
    SCOPED_TRACE(bug);
    Scenario cpp = ring(false, bug), lua = ring(true, bug);
    ASSERT_EQ(lua.model->variable_count(), cpp.model->variable_count());
    sim::Session a(*cpp.model, *cpp.world, {.threads = 1}), b(*lua.model, *lua.world, {.threads = 1});
    for (int64_t t = 0; t < 120; ++t) {
      a.run_until(t + 1);  // the state after step t
      b.run_until(t + 1);
      ASSERT_EQ(a.hash().whole(), b.hash().whole()) << "step " << t;
    }
    EXPECT_EQ(a.match_count(0), b.match_count(0));
    EXPECT_EQ(a.matches(0).slots, b.matches(0).slots);
    EXPECT_EQ(a.matches(0).t, b.matches(0).t);
    if (!bug.empty()) {
      EXPECT_GT(b.match_count(0), 0u);
    }
  }
}

// Leader election on a hex sheet, built in or from scenarios/lua/leader_election.lua, under the
// Fig. 2 watchpoint (distributed), counting.
Scenario election(bool lua, bool bug, unsigned threads = 1) {
  const std::string program =
      lua ? std::string("[[program]]\nscript = \"leader_election.lua\"\nbug = ") + (bug ? "1" : "0")
          : std::string("[[program]]\nname = \"leader_election\"\nbug = ") + (bug ? "true" : "false");
  const std::string text = "threads = " + std::to_string(threads) + "\n[lattice]\nkind = \"hex2d\"\nsize = [12, 10]\n" +
                           program + "\n[[watch]]\nname = \"two_leaders\"\naction = \"log\"\n" +
                           "text = \"modules(a b c); (a.isLeader = 1) and (c.isLeader = 1)\"\n";
  auto loaded = load_scenario_text((kLua / "inline.toml").string(), text);
  if (auto* e = std::get_if<std::string>(&loaded)) ADD_FAILURE() << *e;
  return std::move(std::get<Scenario>(loaded));
}

TEST(LuaProgram, LeaderElectionPortGivesTheTwinsStateEveryStepAndTheSameMatches) {
  for (bool bug : {false, true}) {
    SCOPED_TRACE(bug ? "bug" : "correct");
    Scenario cpp = election(false, bug), lua = election(true, bug, 2);
    sim::Session a(*cpp.model, *cpp.world, {.threads = 1}), b(*lua.model, *lua.world, {.threads = 2});
    for (int64_t t = 0; t < 40; ++t) {
      a.run_until(t + 1);
      b.run_until(t + 1);
      ASSERT_EQ(a.hash().whole(), b.hash().whole()) << "step " << t;
    }
    EXPECT_EQ(a.matches(0).slots, b.matches(0).slots);
    EXPECT_EQ(a.matches(0).t, b.matches(0).t);
    EXPECT_EQ(b.match_count(0) > 0, bug);
  }
}

// The shipped scenario and its Lua twin (same lattice, root and landmarks, the same watchpoint).
TEST(LuaProgram, AggregationRoutingPortGivesTheTwinsStateEveryStepAndTheSameMatches) {
  auto cpp_loaded = load_scenario(std::string(DWATCH_SCENARIOS_DIR) + "/aggregation_routing.toml");
  auto lua_loaded = load_scenario((kLua / "aggregation_routing.toml").string());
  ASSERT_TRUE(std::holds_alternative<Scenario>(cpp_loaded)) << std::get<std::string>(cpp_loaded);
  ASSERT_TRUE(std::holds_alternative<Scenario>(lua_loaded)) << std::get<std::string>(lua_loaded);
  Scenario &cpp = std::get<Scenario>(cpp_loaded), &lua = std::get<Scenario>(lua_loaded);
  ASSERT_EQ(lua.model->variable_count(), cpp.model->variable_count());
  sim::Session a(*cpp.model, *cpp.world, {.threads = 1}), b(*lua.model, *lua.world, {.threads = 2});
  for (int64_t t = 0; t < 60; ++t) {
    a.run_until(t + 1);
    b.run_until(t + 1);
    ASSERT_EQ(a.hash().whole(), b.hash().whole()) << "step " << t;
  }
  // The tree has formed: the root counts every module.
  EXPECT_EQ(b.state().values[2], int64_t(lua.model->module_count()));
  EXPECT_EQ(a.match_count(0), b.match_count(0));
}

TEST(LuaProgram, TheReadmesGradientExampleFindsEveryHopDistance) {
  auto loaded = load_scenario((kLua / "gradient.toml").string());
  ASSERT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
  Scenario& s = std::get<Scenario>(loaded);
  sim::Session run(*s.model, *s.world, {.threads = 2});
  run.run_until(s.steps);
  const std::vector<int> hops = test::bfs(*run.state().graph, 65);
  for (sim::ModuleId m = 0; m < s.model->module_count(); ++m)
    EXPECT_EQ(run.state().values[m], hops[m]) << "module " << m;
  EXPECT_GT(run.match_count(0), 0u);
}

TEST(LuaProgram, SameStatesOnAnyThreadCountAndThroughRollback) {
  Scenario one = ring(true, "duplicate_at = 40", 1), two = ring(true, "duplicate_at = 40", 2);
  sim::Session a(*one.model, *one.world, {.threads = 1}), b(*two.model, *two.world, {.threads = 2});
  a.run_until(90);
  b.run_until(90);
  EXPECT_EQ(a.hash().whole(), b.hash().whole());
  const uint64_t at89 = a.hash().whole();
  ASSERT_TRUE(a.seek(30));
  EXPECT_NE(a.hash().whole(), at89);
  ASSERT_TRUE(a.seek(89));  // re-simulated from a keyframe
  EXPECT_EQ(a.hash().whole(), at89);
}

// slide.lua senses its position and moves in the Bullet world exactly as its C++ twin does.
TEST(LuaProgram, SlidePortMovesInTheWorldAsItsTwinDoes) {
  auto cpp_loaded = load_scenario(std::string(DWATCH_SCENARIOS_DIR) + "/slide.toml");
  auto lua_loaded = load_scenario((kLua / "slide.toml").string());
  ASSERT_TRUE(std::holds_alternative<Scenario>(cpp_loaded)) << std::get<std::string>(cpp_loaded);
  ASSERT_TRUE(std::holds_alternative<Scenario>(lua_loaded)) << std::get<std::string>(lua_loaded);
  Scenario &cpp = std::get<Scenario>(cpp_loaded), &lua = std::get<Scenario>(lua_loaded);
  sim::Session a(*cpp.model, *cpp.world, {.threads = 1}), b(*lua.model, *lua.world, {.threads = 1});
  const uint32_t v = lua.model->variable_count(), cell_x = uint32_t(lua.model->column("cell_x"));
  std::vector<int64_t> start;
  for (int64_t t = 0; t < 80; ++t) {
    a.run_until(t + 1);
    b.run_until(t + 1);
    ASSERT_EQ(a.hash().whole(), b.hash().whole()) << "step " << t;
    if (t == 0)
      for (sim::ModuleId m = 0; m < lua.model->module_count(); ++m) start.push_back(b.state().values[m * v + cell_x]);
  }
  int64_t furthest = 0;  // the furthest a module has slid along x
  for (sim::ModuleId m = 0; m < lua.model->module_count(); ++m)
    furthest = std::max(furthest, b.state().values[m * v + cell_x] - start[m]);
  EXPECT_GE(furthest, 4) << "the train moved";
  EXPECT_EQ(a.matches(0).slots, b.matches(0).slots);
  EXPECT_GT(b.match_count(0), 0u);
}

}  // namespace
}  // namespace dw::scenarios
