// A Lua state a script from someone else can run in without hanging or exhausting the machine.
//
// What a script may call: the base functions that touch nothing outside the script, and the
// string, table, math (without its random numbers) and utf8 libraries, behind guards that make
// every one of them bounded in time: work that grows with the size of the arguments is charged to
// the instruction budget before it is done, and a pattern whose backtracking could take more than
// the pattern limit is refused (string.find and friends). table.sort is a stable merge sort in
// Lua, counted like the script's own code and the same on every machine (Lua's own picks pivots
// from the clock). Finalizers (__gc) and weak tables (__mode) are refused: they run or forget at
// the collector's whim. What Lua leaves to hash seeds and addresses is made the same on every run
// (lua_fixed_order.cpp): pairs and next visit keys in a fixed order, and tostring and
// string.format show no addresses (format's %p is refused).
//
// Three limits stop a call, and none can be caught: once one is reached, every further
// instruction raises the stop again (a pcall, an xpcall's handler, a __close all meet it), until
// the call returns to dwatch.
//   - the instruction budget, counted only when a call is run counted (see LuaWatchdog);
//   - the memory cap of the state, reached when an allocation does not fit even after a full
//     collection (a library function building its result in lauxlib's buffer, which asks the
//     allocator without collecting first, is tried again after one); the same for the run's
//     pool, shared by all its states (scenarios/lua_host/lua_memory_pool.h);
//   - the deadline: a counted call still running after it is stopped, for work the count cannot
//     see (comparing two long strings is one instruction).
#pragma once

#include <lua.hpp>

#include <chrono>
#include <memory>
#include <string>

#include "scenarios/lua_host/lua_memory_pool.h"
#include "scenarios/lua_host/lua_watchdog.h"

namespace dw::scenarios {

// Limits of one Lua state.
struct LuaLimits {
  int64_t instructions = 10'000'000;  // VM instructions per init/step call, library work included
  size_t memory_bytes = 64u << 20;    // per Lua state (one per stepping thread)
  // Calls run uncounted, at full speed; one still running after this long is run again with
  // every instruction counted (scenarios/lua_host/lua_watchdog.h). Zero: every call counted.
  std::chrono::milliseconds patience{10};
  // Wall-clock time a counted call may take.
  std::chrono::milliseconds deadline{10'000};
  // Steps a pattern's backtracking may take at worst in one call of string.find, match, gmatch
  // or gsub.
  double pattern_steps = 1e8;
  // Program messages one init/step call may send (a broadcast sends one per neighbour): what a
  // module's outbox may hold stays in proportion to the ensemble.
  uint32_t messages = 65'536;
  // Shared by every state of a run (one per script per stepping thread); none: no shared limit.
  std::shared_ptr<LuaMemoryPool> pool;
};

class LuaSandbox {
 public:
  // The name of dwatch's own chunks run in the state: a stop inside one is reported at the
  // script's name, not at a line of dwatch's.
  static constexpr const char* kHostChunk = "=[dwatch sandbox]";

  // `display` names the script in messages. The state's calls are watched by `watchdog` when
  // given (one of the same thread, with the same limits), else by one of its own, made at the
  // first call.
  LuaSandbox(const std::string& display, const LuaLimits& limits, LuaWatchdog* watchdog = nullptr);
  ~LuaSandbox();
  LuaSandbox(const LuaSandbox&) = delete;
  LuaSandbox& operator=(const LuaSandbox&) = delete;

  lua_State* state() const { return L_; }  // nullptr when there was no memory for it
  LuaWatchdog& watchdog();
  const LuaLimits& limits() const { return limits_; }
  static LuaSandbox& of(lua_State* L);

  // The functions the guards are made of, as a table on the stack: a freeze of the script's
  // reachable state skips them (they keep nothing).
  void push_guards() const;
  // What a freeze of the script's state calls, as the sandbox had it before the script ran, as a
  // table on the stack: next (Lua's own), pairs, type, error, rawget, tostring and string.sub.
  void push_library() const;

  enum class Outcome {
    kOk,
    kFailed,       // the error message is on the stack
    kInterrupted,  // an uncounted call ran past its patience: take back what it did, run it counted
  };
  // lua_pcall of the function under `args` arguments, counted or uncounted.
  Outcome call(int args, int results, bool counted);

 private:
  enum class Stop { kNone, kInstructions, kMemory, kPool };
  static void* allocate(void* self, void* ptr, size_t old_size, size_t new_size);
  static void count_hook(lua_State* L, lua_Debug*);
  static void stop_hook(lua_State* L, lua_Debug*);
  [[noreturn]] static void stop(lua_State* L, Stop why, int level);
  static int charge(lua_State* L);
  static void charge(lua_State* L, double units);
  static int ordered_pairs(lua_State* L);
  static int ordered_next(lua_State* L);
  static int plain_tostring(lua_State* L);
  static void push_plain_string(lua_State* L, int index);
  static int charge_text(lua_State* L);
  static int check_pattern(lua_State* L);
  static int metatable_write(lua_State* L);
  static int set_metatable(lua_State* L);
  static int buffered(lua_State* L);
  static int plain_concat(lua_State* L);
  static int plain_format(lua_State* L);
  static int replaying(lua_State* L);
  static int replacement(lua_State* L);
  static int describe_error(lua_State* L);
  bool take_from_pool(size_t bytes);
  void return_to_pool();
  void open_libraries();
  void push_stop_message(Stop why);
  std::chrono::milliseconds tick() const;  // of the watchdog

  LuaLimits limits_;
  std::string display_;
  lua_State* L_ = nullptr;
  size_t bytes_ = 0;
  size_t pooled_ = 0;  // taken from limits_.pool: bytes_ rounded up to granules, and one more at most
  // What dwatch itself does in the state between calls (making the host's tables, pushing a stop's
  // message after the memory was found full) is not under a protected call, where a refused
  // allocation is Lua's panic: it may go this far past the cap, which a script cannot reach.
  static constexpr size_t kHostHeadroom = size_t{1} << 20;
  bool in_call_ = false;
  int64_t executed_ = 0;
  Stop stop_ = Stop::kNone;
  std::string where_;  // "script.lua:LINE: " of an instruction-budget stop
  // The last allocation refused: the same one asked again (after Lua's emergency collection)
  // means the memory is truly full.
  const void* refused_ptr_ = nullptr;
  size_t refused_size_ = 0;
  Stop refused_why_ = Stop::kMemory;  // what refused it: the state's cap or the run's pool
  int guards_ = LUA_NOREF;
  int library_ = LUA_NOREF;
  LuaWatchdog* watchdog_ = nullptr;
  std::unique_ptr<LuaWatchdog> own_watchdog_;
};

}  // namespace dw::scenarios
