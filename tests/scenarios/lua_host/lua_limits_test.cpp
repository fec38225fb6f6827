// The limits of a host program in Lua (scenarios/lua_host/lua_program.h) as a run meets them: the
// memory cap against what dwatch makes from a declaration, the pool every state of a run shares,
// and a call run again counted (after the watchdog, an error or a limit), which leaves no trace and
// stops alike whatever ran before it.
#include "scenarios/lua_host/lua_program.h"

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <set>

#include "scenarios/table_reader.h"
#include "tests/scenarios/lua_host/lua_script.h"

namespace dw::scenarios {
namespace {

using test::kHeader;
using test::LuaScript;

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

// m:get and m:set find a variable by a hash lookup, not a scan of the declared names: with 10,000
// variables a call costs about what it costs with one (a scan took 1.67 s a call at 100,000).
TEST_F(LuaScript, GetAndSetDoNotScanTheVariables) {
  const auto seconds_of = [&](int variables) {
    const std::string script = "local t = {}\nfor i = 1, " + std::to_string(variables) +
                               " do t[i] = 'v' .. i end\nprogram = { vars = t }\n"
                               "function step(m) local s = 0\n"
                               "  for i = 1, 20000 do s = s + m:get('v" +
                               std::to_string(variables) + "') end\n  m:set('v" + std::to_string(variables) +
                               "', s) end\n";
    auto loaded = load(script);
    EXPECT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
    Scenario& s = std::get<Scenario>(loaded);
    sim::Session run(*s.model, *s.world, {.threads = 1});
    const auto started = std::chrono::steady_clock::now();
    run.run_until(1);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  };
  const double one = seconds_of(1), many = seconds_of(10000);
  EXPECT_LT(many, 5 * one + 0.05) << "1 variable: " << one << " s, 10,000: " << many << " s";
}

// Besides each call's 10 s, the run's Lua calls together have a wall-clock bound (--lua-seconds):
// a script taking a while on every module stops once the run's calls have taken it.
TEST_F(LuaScript, TheRunsLuaCallsTogetherHaveATimeBound) {
  const std::string script = kHeader + "function step(m) local s = 0 for i = 1, 1000000 do s = s + i end end\n";
  auto loaded = load(script);
  ASSERT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
  Scenario& s = std::get<Scenario>(loaded);
  s.lua_memory->set_seconds(1);
  sim::Session run(*s.model, *s.world, {.threads = 1});
  std::string error;
  const auto started = std::chrono::steady_clock::now();
  try {
    run.run_until(1000);
  } catch (const sim::ProgramError& e) {
    error = e.what();
  }
  EXPECT_NE(error.find("the run's Lua calls took more than 1 s of wall-clock time together (--lua-seconds raises it)"),
            std::string::npos)
      << error;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(), 20);
}

}  // namespace
}  // namespace dw::scenarios
