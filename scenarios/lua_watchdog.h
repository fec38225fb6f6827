// Stops a Lua call that runs too long without slowing down the calls that do not (DESIGN §11).
//
// Counting a script's instructions with a count hook costs the VM a check on every instruction,
// about a third of a typical script's time, to catch the rare call that runs away. Instead, a
// watcher thread looks at the calls every `patience`; one it finds still running a second time is
// interrupted the way lua.c stops a script on Ctrl-C: a signal to the calling thread, whose
// handler installs a hook (lua_sethook may be called from a signal handler) that raises an error
// only this class makes. The caller then takes back what the call did and runs it again under the
// counting hook, so whether a call exceeds its instruction budget never depends on timing.
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
  LuaWatchdog(lua_State* L, std::chrono::milliseconds patience);
  ~LuaWatchdog();
  LuaWatchdog(const LuaWatchdog&) = delete;
  LuaWatchdog& operator=(const LuaWatchdog&) = delete;

  // The calling thread starts a call into the state, and ends it.
  void begin();
  void end();

  // Whether the error value at `index` is the interruption (the call must be run again).
  static bool is_interruption(lua_State* L, int index);

 private:
  static void on_signal(int, siginfo_t* info, void*);
  static void interrupt(lua_State* L, lua_Debug*);
  void watch();

  lua_State* L_;
  std::chrono::milliseconds patience_;
  std::atomic<uint64_t> calls_{0};  // odd while a call runs, one more at each begin and end
  std::atomic<pthread_t> caller_{};
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread watcher_;
};

}  // namespace dw::scenarios
