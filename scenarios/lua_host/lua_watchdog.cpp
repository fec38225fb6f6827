#include "scenarios/lua_host/lua_watchdog.h"

#include <cerrno>
#include <csignal>

namespace dw::scenarios {
namespace {

// SIGURG: ignored when nobody handles it, and used by no library dwatch links (Go's runtime
// preempts goroutines with it for the same reasons).
constexpr int kSignal = SIGURG;

// The error value that marks an interruption: its address, which no script can make.
constexpr char kInterruption = 0;

// The watchdog whose call this thread is running. A signal handler learns nothing else about the
// thread it interrupts, so this one thread-local is the way in; the signal names its watchdog, and
// a handler that finds another (or none) does nothing.
thread_local LuaWatchdog* t_running = nullptr;

void install_handler(void (*handler)(int, siginfo_t*, void*)) {
  // Signal dispositions belong to the process: installed once, the same for every watchdog.
  static std::once_flag installed;
  std::call_once(installed, [handler] {
    struct sigaction action {};
    action.sa_sigaction = handler;
    action.sa_flags = SA_SIGINFO | SA_RESTART;
    sigemptyset(&action.sa_mask);
    sigaction(kSignal, &action, nullptr);
  });
}

}  // namespace

LuaWatchdog::LuaWatchdog(std::chrono::milliseconds tick) : tick_(tick) {
  install_handler(&LuaWatchdog::on_signal);
  watcher_ = std::thread([this] { watch(); });
}

LuaWatchdog::~LuaWatchdog() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  watcher_.join();
}

void LuaWatchdog::begin(lua_State* L, uint32_t ticks) {
  L_ = L;
  // A hook left by a signal that came after the last call ended would interrupt this one at once.
  if (lua_gethook(L_) == &LuaWatchdog::interrupt) lua_sethook(L_, nullptr, 0, 0);
  hook_ = lua_gethook(L_);
  hook_mask_ = lua_gethookmask(L_);
  hook_count_ = lua_gethookcount(L_);
  interrupted_ = false;
  ticks_.store(ticks, std::memory_order_relaxed);
  caller_.store(pthread_self(), std::memory_order_relaxed);
  t_running = this;
  calls_.store(calls_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
}

void LuaWatchdog::end() {
  t_running = nullptr;
  calls_.store(calls_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
}

bool LuaWatchdog::is_interruption(lua_State* L, int index) { return lua_touserdata(L, index) == &kInterruption; }

void LuaWatchdog::on_signal(int, siginfo_t* info, void*) {
  const int saved = errno;
  LuaWatchdog* w = t_running;
  // A signal meant for a call that has ended is let go here, before it touches the hook of the
  // call running now: putting that hook back would restart its count (Lua keeps no countdown a
  // hook can be read back with) and would drop a limit's stop hook. (calls_ is this thread's.)
  if (w && info->si_value.sival_ptr == w &&
      w->signaled_.load(std::memory_order_acquire) == w->calls_.load(std::memory_order_relaxed))
    lua_sethook(w->L_, &LuaWatchdog::interrupt, LUA_MASKCOUNT, 1);
  errno = saved;
}

void LuaWatchdog::interrupt(lua_State* L, lua_Debug*) {
  LuaWatchdog* w = t_running;
  if (!w) return;
  if (w->signaled_.load(std::memory_order_acquire) != w->calls_.load(std::memory_order_relaxed)) {
    // The signal was meant for the call before this one: this one goes on as it was.
    lua_sethook(L, w->hook_, w->hook_mask_, w->hook_count_);
    return;
  }
  // Stays installed: a script that catches the error with pcall meets it again at its next
  // instruction, until it reaches the caller.
  w->interrupted_ = true;
  lua_pushlightuserdata(L, const_cast<char*>(&kInterruption));
  lua_error(L);
}

void LuaWatchdog::watch() {
  uint64_t seen = 0;
  // When the call `seen` was first seen. A call's ticks are measured on the clock, not counted as
  // the watcher's wake-ups: on a loaded machine a wake-up comes late, and a 10 s deadline of 1,000
  // counted ticks fired after 30 s.
  auto first_seen = std::chrono::steady_clock::now();
  std::unique_lock<std::mutex> lock(mutex_);
  while (!wake_.wait_for(lock, tick_, [this] { return stopping_; })) {
    const uint64_t now = calls_.load(std::memory_order_acquire);
    const auto at = std::chrono::steady_clock::now();
    if (now != seen) first_seen = at;
    // Seen running at two looks, a tick apart at least, and for its ticks less the one it may
    // have run before it was first seen.
    if ((now & 1) != 0 && now == seen && at - first_seen >= tick_ * (ticks_.load(std::memory_order_relaxed) - 1)) {
      signaled_.store(now, std::memory_order_release);
      sigval value{};
      value.sival_ptr = this;
      pthread_sigqueue(caller_.load(std::memory_order_relaxed), kSignal, value);
    }
    seen = now;
  }
}

}  // namespace dw::scenarios
