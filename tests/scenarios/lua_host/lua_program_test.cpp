// Host programs in Lua (scenarios/lua_host/lua_program.h): a port gives its C++ twin's states bit for
// bit, on any thread count and through rollback; the sandbox and its limits; and every mistake a
// script can make, named where it happened.
#include "scenarios/lua_host/lua_program.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "scenarios/table_reader.h"
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

// A scenario of `n` modules in a line running `script` (written next to it), with `params`.
class LuaScript : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dwatch_lua_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::variant<Scenario, std::string> load(const std::string& script, const std::string& params = "", int n = 4) {
    std::ofstream(dir_ / "x.lua") << script;
    const std::string text =
        "[lattice]\nkind = \"line\"\nsize = [" + std::to_string(n) + "]\n[[program]]\nscript = \"x.lua\"\n" + params;
    return load_scenario_text((dir_ / "s.toml").string(), text);
  }
  // The error that stops a run of `steps` steps, or "" when it runs through.
  std::string run_error(const std::string& script, int64_t steps = 5) {
    auto loaded = load(script);
    if (auto* e = std::get_if<std::string>(&loaded)) return "load: " + *e;
    Scenario& s = std::get<Scenario>(loaded);
    sim::Session run(*s.model, *s.world, {.threads = 1});
    try {
      run.run_until(steps);
    } catch (const sim::ProgramError& e) {
      return e.what();
    }
    return "";
  }
  std::string script_path() const { return "x.lua"; }  // as the scenario names it

  fs::path dir_;
};

const std::string kHeader = "program = { vars = { \"v\" }, params = { k = 3 } }\n";

TEST_F(LuaScript, ParametersTakeTheScenariosValueElseTheDeclaredDefault) {
  const std::string script = kHeader + "function step(m) m:set(\"v\", m:param(\"k\") * 10 + m.id) end\n";
  for (const auto& [params, k] : {std::pair{"", 3}, std::pair{"k = 7\n", 7}}) {
    auto loaded = load(script, params);
    ASSERT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
    Scenario& s = std::get<Scenario>(loaded);
    sim::Session run(*s.model, *s.world, {.threads = 1});
    run.run_until(1);  // step 0
    EXPECT_EQ(run.state().values[2], k * 10 + 2);
  }
  auto unknown = load(script, "q = 1\n");
  ASSERT_TRUE(std::holds_alternative<std::string>(unknown));
  EXPECT_NE(std::get<std::string>(unknown).find("q"), std::string::npos) << std::get<std::string>(unknown);
}

TEST_F(LuaScript, MessagesNeighboursRandomAndInitFollowTheApi) {
  // Each module sends its id to its right neighbour; at the next step the receiver records the
  // sender. init sets v to 100 + id, which step 0 reads.
  const std::string script =
      "program = { vars = { \"from\", \"first\", \"r\" } }\n"
      "function init(m) m:set(\"first\", 100 + m.id) end\n"
      "function step(m)\n"
      "  if m.step == 0 then m:set(\"first\", m:get(\"first\") + 1) end\n"
      "  for _, msg in ipairs(m:inbox()) do m:set(\"from\", msg.from * 10 + msg.data[1]) end\n"
      "  local n = m:neighbors()\n"
      "  if n[#n] > m.id then m:send(n[#n], { m.id }) end\n"
      "  m:set(\"r\", m:random(1000) * 1000 + m:random(1000))\n"
      "end\n";
  auto loaded = load(script);
  ASSERT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
  Scenario& s = std::get<Scenario>(loaded);
  sim::Session run(*s.model, *s.world, {.threads = 1});
  run.run_until(2);                    // through step 1
  const auto& v = run.state().values;  // [module * 3 + variable]
  for (int m = 1; m < 4; ++m) EXPECT_EQ(v[size_t(m) * 3], (m - 1) * 10 + (m - 1)) << m;
  for (int m = 0; m < 4; ++m) EXPECT_EQ(v[size_t(m) * 3 + 1], 101 + m) << "init, then step 0 read it";
  EXPECT_NE(v[2] / 1000, v[2] % 1000) << "two draws in a step are two numbers";
}

TEST_F(LuaScript, ASyntaxErrorIsALoadErrorNamingTheScriptLine) {
  auto loaded = load(kHeader + "function step(m)\n  m:set(\"v\", )\nend\n");
  ASSERT_TRUE(std::holds_alternative<std::string>(loaded));
  const std::string& e = std::get<std::string>(loaded);
  EXPECT_NE(e.find("s.toml:5:10: error: the script does not load:"), std::string::npos) << e;
  EXPECT_NE(e.find(script_path() + ":3: unexpected symbol near ')'"), std::string::npos) << e;
}

TEST_F(LuaScript, AScriptThatDoesNotDeclareItselfIsALoadError) {
  for (const auto& [script, why] :
       {std::pair{"function step(m) end", "the script must set `program = { vars = {...} }`"},
        std::pair{"program = { vars = { 1 } }\nfunction step(m) end", "`program.vars` must list names"},
        std::pair{"program = { vars = {} }", "the script must define `function step(m)`"},
        std::pair{"program = { vars = {}, params = { k = 1.5 } }\nfunction step(m) end",
                  "`program.params` must map names to integers"}}) {
    auto loaded = load(script);
    ASSERT_TRUE(std::holds_alternative<std::string>(loaded)) << script;
    EXPECT_NE(std::get<std::string>(loaded).find(why), std::string::npos) << std::get<std::string>(loaded);
  }
}

TEST_F(LuaScript, RuntimeErrorsNameTheScriptLineTheModuleAndTheStep) {
  const std::string e =
      run_error(kHeader + "function step(m)\n  if m.step == 2 and m.id == 1 then\n    local x = nil + 1\n  end\nend\n");
  EXPECT_NE(e.find("on module 1 at step 2: " + script_path() + ":4: attempt to perform arithmetic on a nil value"),
            std::string::npos)
      << e;
}

TEST_F(LuaScript, MisusingTheApiIsAnErrorAtTheCallersLine) {
  const std::string p = script_path();
  EXPECT_NE(run_error(kHeader + "function step(m)\n  m:set(\"w\", 1)\nend\n")
                .find(p + ":3: 'w' is not a variable of this program"),
            std::string::npos);
  EXPECT_NE(run_error(kHeader + "function step(m)\n  m:set(\"v\", 1.5)\nend\n")
                .find(p + ":3: a variable's value must be an integer, not 1.5"),
            std::string::npos);
  EXPECT_NE(run_error(kHeader + "function step(m)\n  if m.id == 0 then m:send(3, { 1 }) end\nend\n")
                .find(p + ":3: module 0 sent to 3, which is not its neighbour"),
            std::string::npos);
  EXPECT_NE(run_error(kHeader + "function step(m)\n  m:broadcast({ 1, 2, 3, 4, 5, 6, 7, 8, 9 })\nend\n")
                .find(p + ":3: a message holds at most 8 integers, not 9"),
            std::string::npos);
  EXPECT_NE(run_error(kHeader + "function step(m)\n  m:param(\"z\")\nend\n").find(p + ":3: 'z' is not a parameter"),
            std::string::npos);
  EXPECT_NE(run_error(kHeader + "function step(m)\n  m:broadcast({ 1, \"two\" })\nend\n")
                .find(p + ":3: a message word must be an integer, not string"),
            std::string::npos);
}

TEST_F(LuaScript, StateOutsideTheVariablesIsAnError) {
  const std::string p = script_path();
  // A global written while stepping, new or old.
  EXPECT_NE(run_error(kHeader + "function step(m)\n  count = 1\nend\n").find(p + ":3: writes 'count' outside"),
            std::string::npos);
  EXPECT_NE(run_error(kHeader + "seen = 0\nfunction step(m)\n  seen = seen + 1\nend\n").find(p + ":4: writes 'seen'"),
            std::string::npos);
  // A table reached from a global, and a library.
  EXPECT_NE(run_error(kHeader + "cache = {}\nfunction step(m)\n  cache[m.id] = 1\nend\n").find(p + ":4: writes '0'"),
            std::string::npos);
  EXPECT_NE(run_error(kHeader + "function step(m)\n  string.x = 1\nend\n").find(p + ":3: writes 'x'"),
            std::string::npos);
  // Strings' shared metatable is out of reach, and their methods still work.
  EXPECT_NE(run_error(kHeader + "function step(m)\n  getmetatable('').x = 1\nend\n").find(p + ":3: attempt to index"),
            std::string::npos);
  EXPECT_EQ(run_error(kHeader + "function step(m)\n  m:set(\"v\", #(\"ab\"):rep(3))\nend\n"), "");
  // A local of the script, written by step.
  EXPECT_NE(run_error(kHeader + "local n = 0\nfunction step(m)\n  n = n + 1\nend\n").find("step wrote the local 'n'"),
            std::string::npos);
  // A local that is nil (the fuzzer's crash: the checks' list lost its alignment at a nil value).
  EXPECT_NE(run_error(kHeader + "local unset\nlocal base = { 1 }\nfunction step(m)\n  unset = base[1]\nend\n")
                .find("step wrote the local 'unset'"),
            std::string::npos);
  // Reading them, and local tables of a call, are fine.
  EXPECT_EQ(run_error(kHeader + "local base = { 5 }\nK = 2\nfunction step(m)\n  local t = {}\n  t[1] = base[1] * K\n"
                                "  m:set(\"v\", #base + t[1])\nend\n"),
            "");
}

TEST_F(LuaScript, TablesWithMetatablesAreFrozenToAndClassesStillWork) {
  // A class: its methods behind __index, instances made while stepping.
  EXPECT_EQ(
      run_error(kHeader + "local Vec = {}\nVec.__index = Vec\nfunction Vec.new(x) return setmetatable({ x = x }, Vec) "
                          "end\nfunction Vec:double() return 2 * self.x end\nfunction step(m)\n  if "
                          "Vec.new(m.id):double() ~= 2 * m.id then error('wrong') end\n  m:set('v', 1)\nend\n"),
      "");
  // A metatable's own __index still answers what the table lacks.
  EXPECT_EQ(run_error(kHeader + "local t = setmetatable({}, { __index = function() return 7 end })\nfunction step(m)\n"
                                "  if t.anything ~= 7 then error('wrong') end\nend\n"),
            "");
  // Its own __pairs and __len still see what it holds.
  EXPECT_EQ(run_error(kHeader + "local t = setmetatable({ 5, 6 }, { __len = function(t) return rawlen(t) + 1 end,\n"
                                "  __pairs = function(t) return next, t, nil end })\nfunction step(m)\n"
                                "  local n = 0 for k, v in pairs(t) do n = n + v end\n"
                                "  if n ~= 11 or #t ~= 3 then error(n .. ' ' .. #t) end\nend\n"),
            "");
  // A table that had a metatable when the script loaded is frozen like any other: before, it
  // kept state the thread count and rollbacks changed.
  EXPECT_NE(
      run_error(kHeader + "local keep = setmetatable({ n = 0 }, {})\nfunction step(m)\n  keep.n = keep.n + 1\nend\n")
          .find(script_path() + ":4: writes 'n' outside"),
      std::string::npos);
  EXPECT_NE(run_error(kHeader + "setmetatable(_G, {})\nfunction step(m)\n  n = (n or 0) + 1\nend\n")
                .find(script_path() + ":4: writes 'n' outside"),
            std::string::npos);
  // A metamethod written while stepping is found after the call.
  const std::string e = run_error(kHeader + "local C = {}\nC.__index = C\nfunction step(m)\n  C.__index = {}\nend\n");
  EXPECT_NE(e.find("step wrote '__index' of a table made when the script loaded"), std::string::npos) << e;
  // Replacing what the freeze calls does not stop it.
  EXPECT_NE(run_error(kHeader + "getmetatable = function() return 1 end\nnext = function() end\ntype = nil\n"
                                "cache = {}\nfunction step(m)\n  cache[1] = 1\nend\n")
                .find(script_path() + ":7: writes '1' outside"),
            std::string::npos);
}

TEST_F(LuaScript, NoMetamethodOfTheScriptRunsWhileItIsRead) {
  // These hung for ever (an endless __index) or aborted dwatch (an error raised outside a pcall)
  // when dwatch read `program`, `step` and `init` through the script's metatables.
  EXPECT_EQ(run_error(kHeader + "function step(m) m:set('v', 1) end\n"
                                "setmetatable(_G, { __index = function() while true do end end })\n"),
            "");
  EXPECT_EQ(run_error("program = setmetatable({ vars = { 'v' } }, { __index = function() error('boom') end })\n"
                      "function step(m) m:set('v', 1) end\n"),
            "");
  const std::string e = run_error("setmetatable(_G, { __index = function(_, k) error('no ' .. k) end })\n");
  EXPECT_NE(e.find("x.lua: the script must set `program = { vars = {...} }`"), std::string::npos) << e;
}

TEST_F(LuaScript, ACallSendsAtMostTheMessageLimit) {
  // Two million broadcasts in one step took gigabytes; the limit stops the call at its line.
  const std::string e = run_error(kHeader + "function step(m)\n  for i = 1, 2e6 do m:broadcast({ 1 }) end\nend\n");
  EXPECT_NE(e.find(script_path() + ":3: m:broadcast: this call would send more than 65536 messages"), std::string::npos)
      << e;
  EXPECT_NE(
      run_error(kHeader + "function step(m)\n  if m.id == 0 then for i = 1, 70000 do m:send(1, {}) end end\nend\n")
          .find(script_path() + ":3: m:send: this call would send more than 65536"),
      std::string::npos);
  EXPECT_EQ(run_error(kHeader + "function step(m)\n  for i = 1, 30000 do m:broadcast({ i }) end\nend\n"), "");
}

TEST_F(LuaScript, TheSandboxHasNoFilesProcessesOrLoaders) {
  for (const char* name : {"io", "os", "require", "load", "loadfile", "dofile", "debug", "package", "print"}) {
    const std::string e = run_error(kHeader + "function step(m)\n  local x = " + name + ".x\nend\n");
    EXPECT_NE(e.find("attempt to index a nil value (global '" + std::string(name) + "')"), std::string::npos)
        << name << ": " << e;
  }
  EXPECT_NE(run_error(kHeader + "function step(m)\n  m:set(\"v\", math.random(3))\nend\n")
                .find("attempt to call a nil value (field 'random')"),
            std::string::npos);
}

TEST_F(LuaScript, AnEndlessLoopStopsAtTheInstructionBudget) {
  const std::string e = run_error(kHeader + "function step(m)\n  while true do end\nend\n");
  EXPECT_NE(e.find(script_path() + ":3: ran more than 10000000 instructions in one call"), std::string::npos) << e;
  EXPECT_NE(e.find("on module 0 at step 0"), std::string::npos) << e;
}

TEST_F(LuaScript, NoScriptCatchesItsLimitsOrLeavesAFinalizerBehind) {
  // (scenarios/lua_sandbox_test.cpp tries every way round the limits; this is the run's side.)
  const std::string e =
      run_error(kHeader + "function step(m)\n  while true do pcall(function() while true do end end) end\nend\n");
  EXPECT_NE(e.find("ran more than 10000000 instructions in one call"), std::string::npos) << e;
  EXPECT_NE(e.find("on module 0 at step 0"), std::string::npos) << e;
  // A finalizer would run at exit, after every step went through: refused at load.
  const std::string gc = run_error(kHeader + "keep = setmetatable({}, { __gc = function() while true do end end })\n" +
                                   "function step(m) end\n");
  EXPECT_NE(gc.find("load: "), std::string::npos) << gc;
  EXPECT_NE(gc.find("x.lua:2: setmetatable: finalizers (__gc) are not allowed"), std::string::npos) << gc;
}

TEST_F(LuaScript, VariablesAreNamesAWatchpointCanReadDeclaredOnce) {
  for (const std::string& bad : std::vector<std::string>{"\"\"", "\"a b\"", "\"1x\"", "\"x.y\"", "\"and\"", "\"last\"",
                                                         "\"neighbor\"", "\"" + std::string(256, 'x') + "\""}) {
    const std::string e = run_error("program = { vars = { " + bad + " } }\nfunction step(m) end\n");
    EXPECT_NE(e.find("`program.vars` lists " + bad.substr(0, 81) + (bad.size() > 82 ? "\"" : "") +
                     ", which a watchpoint cannot name"),
              std::string::npos)
        << bad << ": " << e;
  }
  const std::string twice = run_error("program = { vars = { \"x\", \"y\", \"x\" } }\nfunction step(m) end\n");
  EXPECT_NE(twice.find("program x.lua declares the variable 'x' twice"), std::string::npos) << twice;
}

TEST_F(LuaScript, MemoryBeyondTheCapIsAnError) {
  const std::string e =
      run_error(kHeader + "function step(m)\n  local s = string.rep(\"x\", 1 << 27)\nend\n");  // 128 MiB
  EXPECT_NE(e.find("not enough memory"), std::string::npos) << e;
}

TEST_F(LuaScript, TheBodyIsOnlyThereWithPhysics) {
  for (const char* call : {"m:position()", "m:moving()", "m:move(1, 0, 0)", "m:push(0, 0, 1)", "m:pivot(1, 1, 0, 0)"}) {
    const std::string e = run_error(kHeader + "function step(m)\n  " + call + "\nend\n");
    EXPECT_NE(e.find(script_path() + ":3: m:"), std::string::npos) << call << ": " << e;
    EXPECT_NE(e.find("needs a body, and this world has none"), std::string::npos) << call << ": " << e;
  }
}

// m:pivot rolls a sphere of a line over its neighbour into the cell beside both; about a module
// that is not a neighbour it is an error naming both.
TEST_F(LuaScript, PivotRollsOverANeighbourAndNamesAWrongOne) {
  const std::string roll =
      kHeader + "function step(m)\n  if m.id == 3 and m.step == 1 then m:pivot(2, -0.5, " + "0.8660254, 0) end\nend\n";
  auto loaded = load(roll, "[physics]\nenabled = true\nmove_steps = 10\n");
  ASSERT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
  Scenario& s = std::get<Scenario>(loaded);
  sim::Session run(*s.model, *s.world, {.threads = 1});
  run.run_until(5);
  EXPECT_TRUE(run.state().bodies.moving(3));
  run.run_until(13);
  const auto& at = run.state().bodies.poses[3].position;
  EXPECT_NEAR(at[0], 2.5f, 1e-5f);
  EXPECT_NEAR(at[1], 0.8660254f, 1e-5f);
  EXPECT_EQ(std::vector<sim::ModuleId>(run.state().graph->neighbors(3).begin(), run.state().graph->neighbors(3).end()),
            std::vector<sim::ModuleId>{2});

  std::ofstream(dir_ / "x.lua") << kHeader + "function step(m)\n  if m.id == 3 then m:pivot(0, 1, 0, 0) end\nend\n";
  auto wrong = load_scenario_text((dir_ / "s.toml").string(),
                                  "[lattice]\nkind = \"line\"\nsize = [4]\n[[program]]\nscript = \"x.lua\"\n"
                                  "[physics]\nenabled = true\n");
  ASSERT_TRUE(std::holds_alternative<Scenario>(wrong));
  sim::Session bad(*std::get<Scenario>(wrong).model, *std::get<Scenario>(wrong).world, {.threads = 1});
  try {
    bad.run_until(3);
    ADD_FAILURE() << "no error";
  } catch (const sim::ProgramError& e) {
    EXPECT_NE(std::string(e.what()).find("module 3 pivots about 0, which is not its neighbour"), std::string::npos)
        << e.what();
  }
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

// Names longer than Lua interns are found all the same.
TEST_F(LuaScript, LongVariableAndParameterNamesWork) {
  const std::string v(60, 'v'), k(50, 'k');
  const std::string script = "program = { vars = { \"a\", \"" + v + "\" }, params = { " + k +
                             " = 4 } }\nfunction step(m) m:set(\"" + v + "\", m:param(\"" + k + "\") + m:get(\"" + v +
                             "\")) end\n";
  auto loaded = load(script);
  ASSERT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
  Scenario& s = std::get<Scenario>(loaded);
  sim::Session run(*s.model, *s.world, {.threads = 1});
  run.run_until(3);
  EXPECT_EQ(run.state().values[1], 12);
}

// A Lua program with `limits` in place of the scenario's, on its lattice and world.
std::unique_ptr<sim::Model> with_limits(const Scenario& s, const std::string& script, const LuaLimits& limits) {
  const watch::SourceText source("limits.toml", "");
  FileDiagnostics diagnostics(source);
  const toml::table params;
  TableReader reader(params, diagnostics, "[[program]]");
  std::string why;
  std::vector<std::unique_ptr<const sim::HostProgram>> programs;
  programs.push_back(make_lua_program("x.lua", script, reader, why, limits));
  EXPECT_TRUE(programs.back()) << why;
  auto model = sim::build_model(s.model->lattice, std::move(programs), {}, s.model->seed);
  return std::move(std::get<std::unique_ptr<sim::Model>>(model));
}

// Why step 0 of `model` fails on one thread, or "ran through".
std::string first_step_failure(sim::Model& model, sim::World& world) {
  sim::Session run(model, world, {.threads = 1});
  try {
    run.run_until(1);
  } catch (const sim::ProgramError& e) {
    return e.what();
  }
  return "ran through";
}

// The tables dwatch makes in a script's state from its declaration (the names of its variables)
// meet the memory cap as the script's own would: the script is refused with the cap's message,
// where the host's unprotected calls reached Lua's panic and aborted the process (600,000 names
// under 64 MiB did). Some room above the cap is kept for what dwatch does between calls.
TEST(LuaProgram, ADeclarationTooLargeForTheMemoryCapIsRefusedNotAborted) {
  const std::string script =
      "local t = {}\n"
      "for i = 1, 20000 do t[i] = 'v' .. i end\n"
      "program = { vars = t }\n"
      "function step(m) m:set('v1', 1) end\n";
  const watch::SourceText source("cap.toml", "");
  FileDiagnostics diagnostics(source);
  const toml::table params;
  TableReader reader(params, diagnostics, "[[program]]");
  std::string why;
  // Caps from where the script's own table does not fit to where everything does: some cap in
  // between meets the host's tables (without their protected call, this aborts).
  int refused = 0, loaded = 0;
  for (size_t cap = size_t{1} << 20; cap <= size_t{6} << 20; cap += size_t{1} << 17) {
    why.clear();
    if (make_lua_program("x.lua", script, reader, why, {.memory_bytes = cap})) {
      ++loaded;
    } else {
      ++refused;
      EXPECT_NE(why.find("not enough memory"), std::string::npos) << cap << ": " << why;
    }
  }
  EXPECT_GT(refused, 0);
  EXPECT_GT(loaded, 0);
}

// Every Lua state of a run (one per script per stepping thread) takes from one pool, what the
// machine had beyond the scenario's estimate: a state the pool cannot hold is refused saying so,
// however far below its own cap it is, and states give their memory back when they go.
TEST_F(LuaScript, TheRunsLuaStatesTogetherStayWithinTheirSharedPool) {
  const std::string script =
      "program = { vars = { \"v\" } }\n"
      "big = {}\n"
      "for i = 1, 12000 do big[i] = string.rep('x', 1000) .. i end\n"  // about 12 MiB a state
      "function step(m) m:set(\"v\", #big) end\n";
  auto loaded = load(script);
  ASSERT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
  Scenario& s = std::get<Scenario>(loaded);
  EXPECT_EQ(s.lua_memory->used(), 0u) << "the state that checked the script gave its memory back";
  s.lua_memory->set_limit(size_t{20} << 20);
  {
    sim::Session one(*s.model, *s.world, {.threads = 1});
    one.run_until(2);
    EXPECT_EQ(one.state().values[0], 12000);
    EXPECT_GT(s.lua_memory->used(), size_t{12} << 20);
  }
  EXPECT_EQ(s.lua_memory->used(), 0u);
  std::string error;
  try {
    sim::Session two(*s.model, *s.world, {.threads = 2});
    two.run_until(2);
  } catch (const sim::ProgramError& e) {
    error = e.what();
  }
  EXPECT_NE(error.find("x.lua: not enough memory: the run's Lua states (one per script per stepping thread) may hold "
                       "20 MiB together"),
            std::string::npos)
      << error;
  EXPECT_EQ(s.lua_memory->used(), 0u);
}

// A call the watchdog interrupts runs again counted: what the interrupted try set and sent is
// taken back, so the run equals one where every call was counted from the start.
TEST_F(LuaScript, ACallRunAgainAfterTheWatchdogLeavesNoTrace) {
  const std::string script =
      "program = { vars = { \"v\", \"got\" } }\n"
      "function step(m)\n"
      "  local got = 0\n"
      "  for _, msg in ipairs(m:inbox()) do got = got + msg.data[1] end\n"
      "  m:set(\"got\", got)\n"
      "  m:broadcast({ m.id + 1 })\n"
      "  m.step = m.step + 1000\n"  // the try run again must start from the true step
      "  local s = 0\n"
      "  for i = 1, 300000 do s = s + i % 7 end\n"  // a few milliseconds: past a patience of 1 ms
      "  m:set(\"v\", m:get(\"v\") + m.step + s % 5)\n"
      "end\n";
  auto loaded = load(script);
  ASSERT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
  const Scenario& s = std::get<Scenario>(loaded);
  const auto impatient = with_limits(s, script, {.patience = std::chrono::milliseconds(1)});
  const auto counted = with_limits(s, script, {.patience = std::chrono::milliseconds(0)});
  sim::Session a(*impatient, *s.world, {.threads = 1}), b(*counted, *s.world, {.threads = 1});
  for (int64_t t = 0; t < 3; ++t) {
    a.run_until(t + 1);
    b.run_until(t + 1);
    ASSERT_EQ(a.hash().whole(), b.hash().whole()) << "step " << t;
  }
  // One message from each neighbour, none twice: modules 0 1 2 3 in a line.
  const auto& v = a.state().values;  // [module * 2 + variable]
  EXPECT_EQ(v[1], 2);
  EXPECT_EQ(v[3], 1 + 3);
  EXPECT_EQ(v[5], 2 + 4);
  EXPECT_EQ(v[7], 3);
}

// An error names its line whether the call ran uncounted first or counted from the start. Lua
// raises an integer `n % 0` inside its VM without saving the instruction's position unless a hook
// runs, so uncounted it named the line of the last call out (line 3 here, not 5); a failed call
// now runs again counted and that message is reported.
TEST_F(LuaScript, AnErrorRaisedInsideTheVmNamesItsLineUncountedOrCounted) {
  const std::string script =
      "program = { vars = { \"v\" } }\n"
      "function step(m)\n"
      "  local z = m:get(\"v\")\n"
      "  local s = 3\n"
      "  s = s % z\n"
      "  m:set(\"v\", s)\n"
      "end\n";
  auto loaded = load(script);
  ASSERT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
  const Scenario& s = std::get<Scenario>(loaded);
  auto failure = [&](std::chrono::milliseconds patience) {
    return first_step_failure(*with_limits(s, script, {.patience = patience}), *s.world);
  };
  const std::string counted = failure(std::chrono::milliseconds(0));
  EXPECT_NE(counted.find("x.lua:5: attempt to perform 'n%0'"), std::string::npos) << counted;
  EXPECT_EQ(failure(std::chrono::seconds(10)), counted);
}

// A call that meets a limit runs again counted in a state of its own: whether the budget or the
// memory cap stops it, and where, does not depend on what earlier calls grew in the thread's state
// (a deeper stack, more call records) nor on whether it ran uncounted first. Module 1 recurses
// without end, holding a string at each level, near where both limits fall; module 0 first
// recurses `warm` levels deep and returns, on some runs.
TEST_F(LuaScript, ALimitStopsACallAlikeWhateverRanBeforeInItsState) {
  auto script = [](int warm) {
    return "program = { vars = { \"v\" } }\n"
           "local function deep(n)\n"
           "  if n == 0 then return 0 end\n"
           "  local s = string.rep(\"a\", 750)\n"
           "  return deep(n - 1) + #s\n"
           "end\n"
           "function step(m)\n"
           "  if m.id == 0 then deep(" +
           std::to_string(warm) +
           ") end\n"
           "  if m.id == 1 then deep(-1) end\n"
           "end\n";
  };
  auto loaded = load(script(0));
  ASSERT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
  const Scenario& s = std::get<Scenario>(loaded);
  auto stop = [&](int warm, int64_t instructions, std::chrono::milliseconds patience) {
    return first_step_failure(
        *with_limits(s, script(warm), {.instructions = instructions, .memory_bytes = 1u << 20, .patience = patience}),
        *s.world);
  };
  // Budgets on both sides of where the memory cap falls (about 97,000 instructions into the call
  // here), so that both limits are met. Before each counted run had a state of its own, budgets
  // from 95,350 to 96,550 stopped the call by the budget when counted from its start and by the
  // memory cap when it ran uncounted first: the try left Lua's stack grown.
  std::set<std::string> kinds;
  for (int64_t instructions = 91'000; instructions <= 101'000; instructions += 400) {
    SCOPED_TRACE(instructions);
    const std::string fresh = stop(0, instructions, std::chrono::milliseconds(0));
    EXPECT_EQ(fresh.find("x.lua on module 1 at step 0: x.lua"), 0u) << fresh;
    kinds.insert(fresh.find("not enough memory") != std::string::npos ? "memory" : fresh);
    for (int warm : {50, 300})
      EXPECT_EQ(stop(warm, instructions, std::chrono::milliseconds(0)), fresh) << "warm " << warm;
    // Uncounted, the call meets the memory cap (it has no budget) before its patience: it runs
    // again counted.
    EXPECT_EQ(stop(150, instructions, std::chrono::seconds(10)), fresh);
  }
  EXPECT_TRUE(kinds.contains("memory") && kinds.size() >= 2) << "the budgets should reach both limits";
}

// A script fixed while the session runs is loaded again: it runs from the step after the current
// one, on a new branch; the past keeps the old script, re-simulated or not.
TEST_F(LuaScript, AScriptReloadedRunsFromTheNextStepAndThePastKeepsTheOld) {
  const std::string broken = kHeader +
                             "function step(m)\n  if m.step == 6 then error('boom') end\n"
                             "  m:set(\"v\", m:get(\"v\") + 1)\nend\n";
  const std::string fixed = kHeader + "function step(m)\n  m:set(\"v\", m:get(\"v\") + 100)\nend\n";
  auto loaded = load(broken);
  ASSERT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
  Scenario& s = std::get<Scenario>(loaded);
  ASSERT_EQ(s.scripts.size(), 1u);
  sim::Session run(*s.model, *s.world, {.threads = 2});
  try {
    run.run_until(10);
    FAIL() << "the script fails at step 6";
  } catch (const sim::ProgramError& e) {
    EXPECT_EQ(e.step, 6);
    EXPECT_EQ(e.module, 0u);
  }
  ASSERT_EQ(run.latest(), 5);
  ASSERT_TRUE(run.seek(4));
  const uint64_t at2 = (run.seek(2), run.hash().whole());
  ASSERT_TRUE(run.seek(4));

  // A mistake in the new text, or other variables: refused, nothing changes.
  std::ofstream(dir_ / "x.lua") << kHeader + "function step(m)\n  m:set(\"v\", )\nend\n";
  auto refused = reload_scripts(s, run);
  ASSERT_TRUE(std::holds_alternative<std::string>(refused));
  EXPECT_NE(std::get<std::string>(refused).find("x.lua:3:"), std::string::npos) << std::get<std::string>(refused);
  std::ofstream(dir_ / "x.lua") << "program = { vars = { \"w\" } }\nfunction step(m) end\n";
  refused = reload_scripts(s, run);
  ASSERT_TRUE(std::holds_alternative<std::string>(refused));
  EXPECT_NE(std::get<std::string>(refused).find("other variables"), std::string::npos);
  EXPECT_EQ(run.latest(), 5);

  std::ofstream(dir_ / "x.lua") << fixed;
  auto reloaded = reload_scripts(s, run);
  ASSERT_TRUE(std::holds_alternative<std::vector<std::string>>(reloaded)) << std::get<std::string>(reloaded);
  EXPECT_EQ(std::get<std::vector<std::string>>(reloaded), std::vector<std::string>{"x.lua"});
  EXPECT_EQ(run.latest(), 4) << "the future after the current step is dropped";
  run.run_until(10);
  EXPECT_EQ(run.state().values[0], 5 + 5 * 100) << "steps 0..4 the old script, 5..9 the new";
  ASSERT_TRUE(run.seek(2));
  EXPECT_EQ(run.hash().whole(), at2) << "the past keeps the old script";
  EXPECT_EQ(run.state().values[0], 3);
}

}  // namespace
}  // namespace dw::scenarios
