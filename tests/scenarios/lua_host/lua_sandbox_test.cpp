// The sandbox (scenarios/lua_host/lua_sandbox.cpp): no script, however hostile, hangs or exhausts the
// machine, and none can catch the limits that stop it.
#include "scenarios/lua_host/lua_sandbox.h"

#include <gtest/gtest.h>

#include <chrono>
#include <string>

namespace dw::scenarios {
namespace {

using namespace std::chrono_literals;
using Outcome = LuaSandbox::Outcome;
using Clock = std::chrono::steady_clock;

struct Result {
  Outcome outcome;
  std::string message;  // of a failure
  Clock::duration took;
  std::string returned;  // the chunk's first result, as a string, when it ran through
};

// Runs `code` as one call, as a Lua program's step runs: uncounted under the watchdog, then
// counted when the watchdog or a limit interrupted it.
Result run(const std::string& code, const LuaLimits& limits = {}) {
  LuaSandbox box("x.lua", limits);
  lua_State* L = box.state();
  EXPECT_EQ(luaL_loadbufferx(L, code.data(), code.size(), "@x.lua", "t"), LUA_OK) << lua_tostring(L, -1);
  const auto start = Clock::now();
  lua_pushvalue(L, -1);
  Outcome outcome = box.call(0, 1, false);
  if (outcome == Outcome::kInterrupted) outcome = box.call(0, 1, true);
  Result r{outcome, "", Clock::now() - start, ""};
  if (outcome == Outcome::kFailed) r.message = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "(not a string)";
  else if (outcome == Outcome::kOk && lua_type(L, -1) != LUA_TNIL) r.returned = luaL_tolstring(L, -1, nullptr);
  return r;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A failure whose message has `part`, reached within `within`.
void expect_stopped(const std::string& code, const std::string& part, Clock::duration within = 10s,
                    const LuaLimits& limits = {}) {
  const Result r = run(code, limits);
  EXPECT_EQ(r.outcome, Outcome::kFailed) << code;
  EXPECT_TRUE(has(r.message, part)) << code << "\n  gave: " << r.message;
  EXPECT_LT(r.took, within) << code;
}

const std::string kBudget = "ran more than 10000000 instructions in one call";

TEST(LuaSandbox, NoPcallCatchesTheInstructionBudget) {
  expect_stopped("pcall(function() while true do end end)", "x.lua:1: " + kBudget);
  expect_stopped("while true do pcall(function() while true do end end) end", kBudget);
  expect_stopped("while true do xpcall(function() while true do end end, function() while true do end end) end",
                 kBudget);
  expect_stopped("while true do pcall(error, setmetatable({}, {__tostring = function() return 'x' end})) end", kBudget);
  expect_stopped("local function f() return pcall(f) end\nwhile true do f() end", kBudget);
}

TEST(LuaSandbox, NoPcallCatchesTheMemoryCap) {
  expect_stopped(
      "local t = {}\n"
      "while true do pcall(function() for i = 1, 1e9 do t[#t + 1] = string.rep('x', 1 << 20) end end) end",
      "x.lua: not enough memory: a script's Lua state may hold at most 64 MiB");
  expect_stopped("while true do pcall(string.rep, 'x', 1 << 27) end", "not enough memory");
  // Garbage is not a reason to stop: the collector takes it back.
  const Result garbage = run("for i = 1, 100 do local s = string.rep('x', 1 << 20) end return 'ok'");
  EXPECT_EQ(garbage.returned, "ok") << garbage.message;
}

TEST(LuaSandbox, TheDeadlineStopsWorkTheCountCannotSee) {
  // Comparing two 8 MiB strings is one instruction; 10^7 of them would take hours.
  LuaLimits limits;
  limits.deadline = 300ms;
  expect_stopped(
      "local a, b = string.rep('a', 1 << 23), string.rep('a', 1 << 23)\n"
      "while true do pcall(function() while true do local _ = a == b end end) end",
      "x.lua: ran for more than 300 ms of wall-clock time", 5s, limits);
}

TEST(LuaSandbox, BacktrackingPatternsAreRefusedBeforeTheyRun) {
  for (const char* call : {"string.find", "string.match", "string.gmatch", "string.gsub"}) {
    const std::string code = std::string("local s = string.rep('a', 3000)\nlocal r = ") + call +
                             "(s, string.rep('a*', 20) .. 'b', " + (std::string(call) == "string.gsub" ? "''" : "1") +
                             ")\nreturn r";
    expect_stopped(code, "x.lua:2: string.", 2s);
    expect_stopped(code, "backtracking", 2s);
  }
  expect_stopped("return ('a'):rep(3000):find(('a-'):rep(10) .. '%1')", "backtracking", 2s);
  // Ordinary patterns still work, as methods too.
  EXPECT_EQ(run("local k, v = ('key=val'):match('(%w+)=(%w+)') return k .. v").returned, "keyval");
  EXPECT_EQ(run("return (string.gsub('a,b,,c', ',', ';'))").returned, "a;b;;c");
  EXPECT_EQ(run("local n = 0 for w in string.gmatch('one two three', '%a+') do n = n + 1 end return n").returned, "3");
  EXPECT_EQ(run("return string.find('x.y', '.', 1, true)").returned, "2");
}

TEST(LuaSandbox, LibraryWorkIsChargedToTheBudget) {
  expect_stopped("return table.concat(setmetatable({}, {__index = function() return '' end}), '', 1, 1e15)", kBudget);
  expect_stopped("table.move({}, 1, 1e18, 1, {})", kBudget);
  expect_stopped("table.move({}, math.mininteger, math.maxinteger - 1, 1, {})", kBudget);
  expect_stopped("table.insert(setmetatable({}, {__len = function() return 1 << 62 end}), 1, 0)", kBudget);
  expect_stopped("table.remove(setmetatable({}, {__len = function() return 1 << 62 end}), 1)", kBudget);
  expect_stopped("local s = string.rep('\\xe4', 1 << 24)\nwhile true do utf8.len(s) end", kBudget);
  expect_stopped("local s = string.rep('a', 1 << 24)\nwhile true do pcall(string.upper, s) end", kBudget);
  expect_stopped("local s = string.rep('ab', 1e12)", "x.lua:1: ");
  // Copies of nothing cost too: rep loops once a copy (this hung before).
  expect_stopped("local s = string.rep('', 1e15, '')", kBudget);
  expect_stopped("local s = string.rep('', 1 << 62)", kBudget);
  expect_stopped("return string.format('%99999d', 1)", "invalid conversion");
  // Library errors still name the script's line.
  expect_stopped("\nlocal s = string.rep()", "x.lua:2: bad argument #1 to 'string.rep'");
  expect_stopped("local s = ('x'):rep(2, {})", "x.lua:1: bad argument #3 to 'string.rep'");
}

TEST(LuaSandbox, TableSortIsAStableMergeSortWhateverTheComparator) {
  // Stable: equal keys keep their order (Lua's own sort takes pivots from the clock).
  const std::string pairs =
      "local t = {}\nfor i = 1, 500 do t[i] = { key = (i * 7919) % 10, id = i } end\n"
      "table.sort(t, function(a, b) return a.key < b.key end)\n"
      "for i = 2, #t do\n"
      "  if t[i - 1].key > t[i].key or (t[i - 1].key == t[i].key and t[i - 1].id > t[i].id) then return 'bad ' .. i "
      "end\n"
      "end\nreturn 'sorted'";
  EXPECT_EQ(run(pairs).returned, "sorted");
  EXPECT_EQ(run("local t = {5, 3, 9, 1, 1, -4}\ntable.sort(t)\nreturn table.concat(t, ',')").returned, "-4,1,1,3,5,9");
  EXPECT_EQ(
      run("local t = {'b', 'c', 'a'}\ntable.sort(t, function(a, b) return a > b end)\nreturn table.concat(t)").returned,
      "cba");
  // A comparator that lies ends, the same way every time.
  const std::string lies =
      "local t = {}\nfor i = 1, 300 do t[i] = i end\n"
      "table.sort(t, function() return true end)\nreturn table.concat(t, ',')";
  const Result once = run(lies), again = run(lies);
  EXPECT_EQ(once.outcome, Outcome::kOk);
  EXPECT_EQ(once.returned, again.returned);
  // One that fails fails at its own line; one that never ends meets the budget.
  expect_stopped("local t = {3, 2, 1}\ntable.sort(t, function(a, b)\n  error('mine')\nend)", "x.lua:3: mine");
  expect_stopped("table.sort({3, 2, 1}, function() while true do end end)", kBudget);
  expect_stopped("table.sort({3, {}, 1})", "attempt to compare");
}

TEST(LuaSandbox, FinalizersAndWeakTablesAreRefusedAndCloseMeetsTheBudget) {
  expect_stopped("setmetatable({}, {__gc = function() while true do end end})", "x.lua:1: setmetatable: finalizers");
  expect_stopped("setmetatable({}, {__mode = 'k'})", "x.lua:1: setmetatable: weak tables");
  // Set on the metatable afterwards, however it is reached: Lua reads __mode at each collection.
  const std::string refused = "of a table used as a metatable: finalizers and weak tables are not allowed";
  expect_stopped("local mt = {}\nlocal w = setmetatable({}, mt)\nmt.__mode = 'k'", "x.lua:3: sets '__mode' " + refused);
  expect_stopped("local mt = {}\nsetmetatable({}, mt)\nmt.__gc = print", "x.lua:3: sets '__gc' " + refused);
  expect_stopped("local mt = {}\nsetmetatable({}, mt)\nsetmetatable(mt, nil)\nmt.__mode = 'v'",
                 "x.lua:4: sets '__mode'");
  expect_stopped("local mt = {}\nsetmetatable({}, mt)\nsetmetatable(mt, {})\nmt.__mode = 'v'",
                 "x.lua:4: sets '__mode'");
  expect_stopped("local mt = setmetatable({}, {__index = {}})\nsetmetatable({}, mt)\nmt.__mode = 'k'",
                 "x.lua:3: sets '__mode'");
  expect_stopped("local mt = {}\nsetmetatable({}, mt)\ngetmetatable(mt).__newindex = nil",
                 "attempt to index a boolean");
  // What metatables are for still works: classes, their instances, fields set after setmetatable.
  const Result classes =
      run("local Base = {}\nBase.__index = Base\nfunction Base.hello() return 'hi' end\n"
          "local Derived = setmetatable({}, {__index = Base})\nDerived.__index = Derived\n"
          "local o = setmetatable({}, Derived)\no.x = 7\nDerived.extra = 1\n"
          "local mt = {}\nlocal t = setmetatable({}, mt)\nmt.__index = function() return 5 end\n"
          "return o.hello() .. o.x .. o.extra .. t.anything .. tostring(getmetatable(o) == Derived)");
  EXPECT_EQ(classes.returned, "hi715true") << classes.message;
  expect_stopped("do local x <close> = setmetatable({}, {__close = function() while true do end end}) end", kBudget);
  expect_stopped("local t = setmetatable({}, {__index = function(t, k) return t[k] end})\nreturn t.x",
                 "stack overflow");
}

// An error value that is not a string has no position of its own: the message names the line it
// was raised at, and its type. Inside the script, pcall still hands back the value itself.
TEST(LuaSandbox, AnErrorThatIsNotAStringNamesItsLine) {
  expect_stopped("local x = 1\nerror(nil)", "x.lua:2: an error that is not a string (a nil value)");
  expect_stopped("local function f()\n  local t = {}\n  error(t)\nend\nf()",
                 "x.lua:3: an error that is not a string (a table value)");
  expect_stopped("error(setmetatable({}, {__tostring = function() while true do end end}))",
                 "x.lua:1: an error that is not a string (a table value)");
  const Result caught =
      run("local ok, e = pcall(error, nil)\nlocal ok2, e2 = pcall(error, {})\n"
          "return tostring(ok) .. tostring(e) .. type(e2)");
  EXPECT_EQ(caught.returned,
            "falsenil"
            "table")
      << caught.message;
  // A string keeps its message; a limit stays the limit's.
  expect_stopped("error('mine', 0)", "mine");
  expect_stopped("local t = {}\nwhile true do error(t) end", "an error that is not a string");
  expect_stopped("while true do pcall(error, nil) end", kBudget);
}

TEST(LuaSandbox, TheLimitsStayForTheNextCall) {
  // A call that hit a limit leaves nothing behind: the next one has its whole budget.
  LuaSandbox box("x.lua", {});
  lua_State* L = box.state();
  for (const char* code : {"while true do end", "return 1"}) {
    ASSERT_EQ(luaL_loadstring(L, code), LUA_OK);
    const Outcome outcome = box.call(0, 0, true);
    if (std::string(code) == "return 1") EXPECT_EQ(outcome, Outcome::kOk);
    else EXPECT_EQ(outcome, Outcome::kFailed);
    lua_settop(L, 0);
  }
}

}  // namespace
}  // namespace dw::scenarios
