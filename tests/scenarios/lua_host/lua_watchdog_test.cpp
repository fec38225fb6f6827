// The watchdog (scenarios/lua_host/lua_watchdog.cpp) interrupts a call that runs past its patience, and
// only such a call.
#include "scenarios/lua_host/lua_watchdog.h"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <string>

namespace dw::scenarios {
namespace {

using namespace std::chrono_literals;

struct State {
  lua_State* L = luaL_newstate();
  State() { luaL_openlibs(L); }
  ~State() { lua_close(L); }
};

// Runs `code` as one call under the watchdog; true when it was interrupted.
bool interrupted(lua_State* L, LuaWatchdog& watchdog, const char* code) {
  EXPECT_EQ(luaL_loadstring(L, code), LUA_OK);
  watchdog.begin(L);
  const int status = lua_pcall(L, 0, 0, 0);
  watchdog.end();
  const bool was = status != LUA_OK && LuaWatchdog::is_interruption(L, -1);
  lua_settop(L, 0);
  return was;
}

TEST(LuaWatchdog, InterruptsAnEndlessLoopAfterItsPatience) {
  State s;
  LuaWatchdog watchdog(5ms);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_TRUE(interrupted(s.L, watchdog, "while true do end"));
  const auto took = std::chrono::steady_clock::now() - start;
  EXPECT_GE(took, 5ms);
  EXPECT_LT(took, 5s);
}

TEST(LuaWatchdog, AScriptCatchingTheInterruptionMeetsItAgain) {
  State s;
  LuaWatchdog watchdog(5ms);
  EXPECT_TRUE(interrupted(s.L, watchdog, "while true do pcall(function() while true do end end) end"));
}

TEST(LuaWatchdog, LeavesShortCallsAloneAndTheNextCallUntouched) {
  State s;
  LuaWatchdog watchdog(200ms);
  for (int i = 0; i < 1000; ++i)
    ASSERT_FALSE(interrupted(s.L, watchdog, "local x = 0 for i = 1, 100 do x = x + i end"));
  // An error of the script's own is not an interruption.
  ASSERT_EQ(luaL_loadstring(s.L, "error('mine')"), LUA_OK);
  watchdog.begin(s.L);
  EXPECT_NE(lua_pcall(s.L, 0, 0, 0), LUA_OK);
  watchdog.end();
  EXPECT_FALSE(LuaWatchdog::is_interruption(s.L, -1));
}

// A call run again counted runs in a state of its own under the same watchdog: each call is
// interrupted in the state it runs in, and the other state's calls go on untouched.
TEST(LuaWatchdog, ServesTheStatesOfAThreadInTurn) {
  State first, second;
  LuaWatchdog watchdog(5ms);
  EXPECT_FALSE(interrupted(first.L, watchdog, "local x = 0 for i = 1, 100 do x = x + i end"));
  EXPECT_TRUE(interrupted(second.L, watchdog, "while true do end"));
  EXPECT_TRUE(interrupted(first.L, watchdog, "while true do end"));
  EXPECT_FALSE(interrupted(second.L, watchdog, "local x = 0 for i = 1, 100 do x = x + i end"));
}

// A signal for a call that has ended (the watcher saw it running just before it returned) arrives
// while the next call runs: it leaves that call's own count hook alone, its count going on where
// it was, instead of restarting it.
int hook_calls = 0;
void count_calls(lua_State*, lua_Debug*) { ++hook_calls; }
int late_signal(lua_State* L) {
  sigval value{};
  value.sival_ptr = lua_touserdata(L, lua_upvalueindex(1));
  pthread_sigqueue(pthread_self(), SIGURG, value);  // handled before the call returns
  return 0;
}

TEST(LuaWatchdog, ASignalForAnEndedCallLeavesTheNextCallsHookAlone) {
  State s;
  LuaWatchdog watchdog(50ms);                                    // the short calls below never meet it
  ASSERT_TRUE(interrupted(s.L, watchdog, "while true do end"));  // the watcher signals that call
  lua_pushlightuserdata(s.L, &watchdog);
  lua_pushcclosure(s.L, &late_signal, 1);
  lua_setglobal(s.L, "late_signal");
  // Some 1,700 instructions before the signal and 8,500 after (two a loop turn), under a hook
  // every 1,000.
  auto fires = [&](const char* between) {
    const std::string code =
        std::string("local x = 0 for i = 1, 850 do x = x + i end ") + between + " for i = 1, 4250 do x = x + i end";
    hook_calls = 0;
    lua_sethook(s.L, &count_calls, LUA_MASKCOUNT, 1000);
    EXPECT_EQ(luaL_loadstring(s.L, code.c_str()), LUA_OK);
    watchdog.begin(s.L);
    const int status = lua_pcall(s.L, 0, 0, 0);
    watchdog.end();
    EXPECT_EQ(status, LUA_OK) << lua_tostring(s.L, -1);
    lua_settop(s.L, 0);
    lua_sethook(s.L, nullptr, 0, 0);
    return hook_calls;
  };
  const int plain = fires("tostring(1)");
  EXPECT_GE(plain, 9);
  EXPECT_EQ(fires("late_signal()"), plain);
}

}  // namespace
}  // namespace dw::scenarios
