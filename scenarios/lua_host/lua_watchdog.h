// Stops a Lua call that runs too long without slowing down the calls that do not (docs/lua.md,
// "Sandbox").
//
// Counting a script's instructions with a count hook costs the VM a check on every instruction,
// about a third of a typical script's time, to catch the rare call that runs away. Instead, a
// watcher thread looks at the calls every tick; one it finds still running after its ticks is
// interrupted the way lua.c stops a script on Ctrl-C: a signal to the calling thread, whose
// handler installs a hook (lua_sethook may be called from a signal handler) that raises an error
// only this class makes, before every instruction until the call returns, so that no pcall can
// keep it. The caller then takes back what the call did and runs it again under the counting hook
// (scenarios/lua_host/lua_sandbox.h), so whether a call exceeds its instruction budget never depends on
// timing; the counted run is watched too, with a deadline, for work the count cannot see.
#pragma once

#include <pthread.h>
#include <lua.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <mutex>
#include <thread>

namespace dw::scenarios {

class LuaWatchdog {
 public:
  explicit LuaWatchdog(std::chrono::milliseconds tick);
  ~LuaWatchdog();
  LuaWatchdog(const LuaWatchdog&) = delete;
  LuaWatchdog& operator=(const LuaWatchdog&) = delete;

  // The calling thread starts a call into the state L, to be interrupted when it is still running
  // after `ticks` ticks (one tick: after one to two ticks), and ends it. One watchdog serves the
  // states of one thread in turn (a call run again counted runs in a state of its own).
  void begin(lua_State* L, uint32_t ticks = 1);
  void end();

  // Whether the current (or last) call was interrupted.
  bool interrupted() const { return interrupted_; }
  // Whether the error value at `index` is the interruption.
  static bool is_interruption(lua_State* L, int index);

 private:
  static void on_signal(int, siginfo_t* info, void*);
  static void interrupt(lua_State* L, lua_Debug*);
  void watch();

  lua_State* L_ = nullptr;  // of the running call: set and read on the calling thread only
  std::chrono::milliseconds tick_;
  std::atomic<uint64_t> calls_{0};     // odd while a call runs, one more at each begin and end
  std::atomic<uint64_t> signaled_{0};  // the call the watcher last interrupted
  std::atomic<uint32_t> ticks_{1};     // of the running call
  std::atomic<pthread_t> caller_{};
  // The hook the call runs under, put back when a signal meant for an earlier call arrives late.
  lua_Hook hook_ = nullptr;
  int hook_mask_ = 0, hook_count_ = 0;
  bool interrupted_ = false;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread watcher_;
};

}  // namespace dw::scenarios
