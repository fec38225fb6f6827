// What a script may do (scenarios/lua_host/lua_program.h): parameters, messages, neighbours,
// random numbers, init, the body and lattice moves; every mistake a script can make, named where it
// happened; the sandbox as a run meets it; and a script fixed while the session runs.
#include <gtest/gtest.h>

#include <fstream>

#include "tests/scenarios/lua_host/lua_script.h"

namespace dw::scenarios {
namespace {

using test::kHeader;
using test::LuaScript;

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

// A script path may name any file: one that is no .lua script is said to be no Lua, and nothing of
// it is quoted (a syntax error quoted "near '"hunter2-secret...'", issue 62).
TEST_F(LuaScript, AFileThatIsNoLuaScriptIsNotQuoted) {
  std::ofstream(dir_ / "secret.txt") << "password = \"hunter2-secret\n";
  const auto loaded = load_scenario_text(
      (dir_ / "s.toml").string(), "[lattice]\nkind = \"line\"\nsize = [4]\n[[program]]\nscript = \"secret.txt\"\n");
  ASSERT_TRUE(std::holds_alternative<std::string>(loaded));
  const std::string& e = std::get<std::string>(loaded);
  EXPECT_NE(e.find("secret.txt: not Lua source"), std::string::npos) << e;
  EXPECT_EQ(e.find("hunter2"), std::string::npos) << e;
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
  // Lua writes 0/0 as "-nan": a NaN is said "nan" (issue 62).
  EXPECT_NE(run_error(kHeader + "function step(m)\n  m:set(\"v\", 0/0)\nend\n")
                .find(p + ":3: a variable's value must be an integer, not nan"),
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
  // (tests/scenarios/lua_host/lua_sandbox_test.cpp tries every way round the limits; this is the run's side.)
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

// m:move and m:push refuse what is not a finite number (NaN, the infinities, a number past a
// float's range), as m:pivot does: a program error naming the call, never a corrupt pose.
TEST_F(LuaScript, MoveAndPushRefuseWhatIsNotAFiniteNumber) {
  const std::pair<std::string, std::string> cases[] = {{"m:move(0/0, 0, 0)", "m:move: its x is nan"},
                                                       {"m:move(0, math.huge, 0)", "m:move: its y is inf"},
                                                       {"m:push(0, 0, -math.huge)", "m:push: its z is -inf"},
                                                       {"m:push(0/0, 1, 1)", "m:push: its x is nan"},
                                                       {"m:push(1e300, 0, 0)", "m:push: its x is 1e+300"}};
  for (const auto& [call, said] : cases) {
    auto loaded =
        load(kHeader + "function step(m)\n  if m.id == 3 then " + call + " end\nend\n", "[physics]\nenabled = true\n");
    ASSERT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
    Scenario& s = std::get<Scenario>(loaded);
    sim::Session run(*s.model, *s.world, {.threads = 1});
    try {
      run.run_until(2);
      ADD_FAILURE() << call << ": no error, and module 3 is at x = " << run.state().bodies.poses[3].position[0];
    } catch (const sim::ProgramError& e) {
      EXPECT_NE(std::string(e.what()).find("x.lua:3: " + said + ", not a finite number"), std::string::npos)
          << call << ": " << e.what();
    }
  }
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
