#include "scenarios/lua_host/lua_sandbox.h"

#include "scenarios/lua_host/lua_guards.h"
#include "sim/read_file.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string_view>

namespace dw::scenarios {
namespace {

using namespace std::chrono_literals;

constexpr int kHookEvery = 1000;
// Library work is charged one instruction per this many bytes it reads or writes.
constexpr double kBytesPerInstruction = 16;

// The error value of a stop: its address, which no script can make.
constexpr char kStopped = 0;

// "source:LINE: " of the first frame from `level` up that is the script's own (not the library
// nor the guards), or "".
std::string location(lua_State* L, int level) {
  lua_Debug at;
  for (; lua_getstack(L, level, &at); ++level) {
    if (!lua_getinfo(L, "Sl", &at) || at.currentline <= 0) continue;
    if (std::strcmp(at.source, LuaSandbox::kHostChunk) == 0) continue;
    return std::string(at.short_src) + ":" + std::to_string(at.currentline) + ": ";
  }
  return "";
}

// The index just past the single-character class of a Lua pattern at `i` (a character, %x or a
// [set]), or `m` when the pattern ends inside it (the library reports that).
size_t class_end(const char* p, size_t i, size_t m) {
  if (p[i] == '%') return std::min(i + 2, m);
  if (p[i] != '[') return i + 1;
  size_t j = i + 1;
  if (j < m && p[j] == '^') ++j;
  do {  // the first character of a set is never its end, as in lstrlib's classEnd
    if (j >= m) return m;
    if (p[j++] == '%' && j < m) ++j;
  } while (j < m && p[j] != ']');
  return std::min(j + 1, m);
}

// An upper bound on the steps of lstrlib's backtracking matcher for a search of the pattern over
// `n` bytes: every start position, times every way each repeated item (*, +, -, ?), balance (%b)
// and back reference can go, times the pattern's length.
double pattern_steps(size_t n, const char* p, size_t m) {
  const double positions = double(n) + 1;
  double steps = positions * double(m + 1);
  size_t i = 0;
  if (m > 0 && p[0] == '^') {
    steps /= positions;
    i = 1;
  }
  while (i < m) {
    const char c = p[i];
    if (c == '(' || c == ')' || (c == '$' && i + 1 == m)) {
      ++i;
      continue;
    }
    if (c == '%' && i + 1 < m) {
      const char d = p[i + 1];
      if (d == 'b') {
        steps *= positions;
        i += 4;
        continue;
      }
      if (d == 'f') {
        i = i + 2 < m ? class_end(p, i + 2, m) : m;
        continue;
      }
      if (d >= '0' && d <= '9') {
        steps *= positions;
        i += 2;
        continue;
      }
    }
    const size_t end = class_end(p, i, m);
    if (end < m && (p[end] == '*' || p[end] == '+' || p[end] == '-')) {
      steps *= positions;
      i = end + 1;
    } else if (end < m && p[end] == '?') {
      steps *= 2;
      i = end + 1;
    } else {
      i = end;
    }
  }
  return steps;
}

}  // namespace

LuaSandbox::LuaSandbox(const std::string& display, const LuaLimits& limits, LuaWatchdog* watchdog)
    : limits_(limits), display_(display), watchdog_(watchdog) {
  L_ = lua_newstate(&LuaSandbox::allocate, this);
  if (!L_) return;
  // A step's tables live for that step only: the young generation is where they die.
  lua_gc(L_, LUA_GCGEN, 0, 0);
  lua_sethook(L_, &LuaSandbox::count_hook, LUA_MASKCOUNT, kHookEvery);
  // What dwatch does outside a protected call could still meet a machine out of memory (not the
  // cap: under `ulimit -v`), where Lua's default is to abort without a word.
  lua_atpanic(L_, [](lua_State* L) -> int {
    const char* what = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "an error outside a protected call";
    std::fprintf(stderr, "dwatch: error: a Lua state failed: %s\n", what);
    std::_Exit(1);
  });
  // The libraries and guards under a protected call: without the memory for them, the state is
  // not made (state() is null), rather than Lua's panic.
  lua_pushcfunction(L_, [](lua_State* L) -> int {
    of(L).open_libraries();
    return 0;
  });
  if (lua_pcall(L_, 0, 0, 0) != LUA_OK) {
    lua_close(L_);
    L_ = nullptr;
  }
}

LuaSandbox::~LuaSandbox() {
  own_watchdog_.reset();
  if (L_) lua_close(L_);
  if (limits_.pool) limits_.pool->give_back(pooled_);
}

LuaSandbox& LuaSandbox::of(lua_State* L) {
  void* self = nullptr;
  lua_getallocf(L, &self);
  return *static_cast<LuaSandbox*>(self);
}

void LuaSandbox::push_guards() const { lua_rawgeti(L_, LUA_REGISTRYINDEX, guards_); }
void LuaSandbox::push_library() const { lua_rawgeti(L_, LUA_REGISTRYINDEX, library_); }

void* LuaSandbox::allocate(void* self_ptr, void* ptr, size_t old_size, size_t new_size) {
  auto& self = *static_cast<LuaSandbox*>(self_ptr);
  const size_t old = ptr ? old_size : 0;
  if (new_size == 0) {
    std::free(ptr);
    self.bytes_ -= old;
    self.return_to_pool();
    return nullptr;
  }
  const size_t cap = self.limits_.memory_bytes + (self.in_call_ ? 0 : kHostHeadroom);
  const size_t wanted = self.bytes_ - old + new_size;
  const bool over_cap = new_size > old && wanted > cap;
  if (over_cap || (new_size > old && !self.take_from_pool(wanted))) {
    // Lua collects everything it can and asks again: refused twice, the memory is full of what
    // the script holds (or the run's states hold), and the call stops.
    const bool full = new_size > cap || (ptr == self.refused_ptr_ && new_size == self.refused_size_);
    self.refused_ptr_ = ptr;
    self.refused_size_ = new_size;
    self.refused_why_ = over_cap ? Stop::kMemory : Stop::kPool;
    if (full && self.L_) {
      if (self.stop_ == Stop::kNone) self.stop_ = self.refused_why_;
      lua_sethook(self.L_, &LuaSandbox::stop_hook, LUA_MASKCOUNT, 1);
    }
    return nullptr;
  }
  void* p = std::realloc(ptr, new_size);
  if (p) {
    self.bytes_ = wanted;
    self.refused_size_ = 0;
  }
  self.return_to_pool();
  return p;
}

// Granules enough for `bytes`, from the run's pool: dwatch's own work between calls takes them
// whatever the pool holds (it must not fail; a script's next call is refused instead).
bool LuaSandbox::take_from_pool(size_t bytes) {
  if (!limits_.pool || bytes <= pooled_) return true;
  const size_t more =
      (bytes - pooled_ + LuaMemoryPool::kGranule - 1) / LuaMemoryPool::kGranule * LuaMemoryPool::kGranule;
  if (!limits_.pool->take(more, !in_call_)) return false;
  pooled_ += more;
  return true;
}

// Granules beyond one spare go back to the pool, for the run's other states.
void LuaSandbox::return_to_pool() {
  if (!limits_.pool || pooled_ <= bytes_ + 2 * LuaMemoryPool::kGranule) return;
  const size_t keep = (bytes_ / LuaMemoryPool::kGranule + 2) * LuaMemoryPool::kGranule;
  limits_.pool->give_back(pooled_ - keep);
  pooled_ = keep;
}

void LuaSandbox::count_hook(lua_State* L, lua_Debug*) {
  LuaSandbox& s = of(L);
  s.executed_ += kHookEvery;
  if (s.executed_ > s.limits_.instructions) stop(L, Stop::kInstructions, 0);
}

void LuaSandbox::stop_hook(lua_State* L, lua_Debug*) { stop(L, of(L).stop_, 0); }

void LuaSandbox::stop(lua_State* L, Stop why, int level) {
  LuaSandbox& s = of(L);
  if (s.stop_ == Stop::kNone) {
    s.stop_ = why;
    s.where_ = location(L, level);
  }
  // Before every instruction from now on, until the call returns to dwatch. (Nothing with a
  // destructor may be alive here: lua_error jumps over C++ frames.)
  lua_sethook(L, &LuaSandbox::stop_hook, LUA_MASKCOUNT, 1);
  lua_pushlightuserdata(L, const_cast<char*>(&kStopped));
  lua_error(L);
  std::abort();  // lua_error does not return
}

// charge(units): library work about to be done, in instructions.
int LuaSandbox::charge(lua_State* L) {
  charge(L, lua_tonumber(L, 1));
  return 0;
}

// Library work about to be done in a function the script called, in instructions.
void LuaSandbox::charge(lua_State* L, double units) {
  LuaSandbox& s = of(L);
  if (units > 0) s.executed_ += units >= 1e18 ? int64_t(1e18) : int64_t(units);
  if (s.executed_ > s.limits_.instructions) stop(L, Stop::kInstructions, 1);
}

// charge_text(...): one instruction per argument, and the strings' bytes.
int LuaSandbox::charge_text(lua_State* L) {
  double units = lua_gettop(L);
  for (int i = 1; i <= lua_gettop(L); ++i)
    if (lua_type(L, i) == LUA_TSTRING) units += double(lua_rawlen(L, i)) / kBytesPerInstruction;
  lua_settop(L, 0);
  lua_pushnumber(L, units);
  return charge(L);
}

// check_pattern(name, s, p [, plain]): refuses a search whose worst case is over the limit;
// charges its bytes.
// A weak table or a finalizer set on a metatable after setmetatable (`mt.__mode = "k"`) would act
// when the collector decides (Lua reads __mode at each collection). So a table that becomes a
// metatable gets a guard: without a metatable of its own it gets one whose __newindex is
// metatable_write (and hidden, like the frozen globals' own); with one that has no __newindex, that
// one gains metatable_write as its __newindex. A script cannot write a table's absent keys but
// through __newindex (rawset is gone), and set_metatable keeps the guard when the metatable-to-be
// gets a metatable later.
//
// metatable_write(t, k, v): t[k] = v, but for __gc and __mode.
int LuaSandbox::metatable_write(lua_State* L) {
  if (lua_type(L, 2) == LUA_TSTRING) {
    const std::string_view key = lua_tostring(L, 2);
    if (key == "__gc" || key == "__mode") {
      // The script's line that wrote it. (No C++ object may be alive where Lua may raise.)
      char where[256];
      {
        const std::string line = location(L, 0);
        std::snprintf(where, sizeof where, "%s", line.c_str());
      }
      lua_pushstring(L, where);
      lua_pushfstring(L,
                      "sets '%s' of a table used as a metatable: finalizers and weak tables are not allowed (they "
                      "act when the collector decides, which differs from run to run)",
                      lua_tostring(L, 2));
      lua_concat(L, 2);
      return lua_error(L);
    }
  }
  lua_settop(L, 3);
  lua_rawset(L, 1);
  return 0;
}

namespace {

// Whether the table at `index` is guarded (see metatable_write): its real metatable is the guard
// (upvalue 1) or has metatable_write as its __newindex.
bool guarded(lua_State* L, int index, lua_CFunction write) {
  if (!lua_getmetatable(L, index)) return false;
  bool is = lua_rawequal(L, -1, lua_upvalueindex(1));
  if (!is) {
    lua_pushliteral(L, "__newindex");
    lua_rawget(L, -2);
    is = lua_tocfunction(L, -1) == write;
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  return is;
}

// Gives the table at `index`, a metatable, `write` as its __newindex unless it has one.
void ensure_newindex(lua_State* L, int index, lua_CFunction write) {
  index = lua_absindex(L, index);
  lua_pushliteral(L, "__newindex");
  if (lua_rawget(L, index) == LUA_TNIL) {
    lua_pushliteral(L, "__newindex");
    lua_pushcfunction(L, write);
    lua_rawset(L, index);
  }
  lua_pop(L, 1);
}

// Makes the table at `index` one whose absent keys a script writes only through `write` (or a
// __newindex of its own metatable's).
void guard_table(lua_State* L, int index, lua_CFunction write) {
  index = lua_absindex(L, index);
  if (!lua_getmetatable(L, index)) {
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_setmetatable(L, index);
    return;
  }
  ensure_newindex(L, -1, write);
  lua_pop(L, 1);
}

}  // namespace

// set_metatable(t, mt): setmetatable, the metatable-to-be guarded (see metatable_write).
int LuaSandbox::set_metatable(lua_State* L) {
  luaL_checktype(L, 1, LUA_TTABLE);
  const int type = lua_type(L, 2);
  luaL_argexpected(L, type == LUA_TNIL || type == LUA_TTABLE, 2, "nil or table");
  lua_settop(L, 2);
  const bool was_guarded = guarded(L, 1, &metatable_write);
  if (!was_guarded && luaL_getmetafield(L, 1, "__metatable") != LUA_TNIL)
    return luaL_error(L, "cannot change a protected metatable");
  lua_settop(L, 2);
  if (was_guarded && type == LUA_TNIL) {
    // t is some table's metatable: it keeps the guard in place of none.
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_replace(L, 2);
  } else if (was_guarded) {
    ensure_newindex(L, 2, &metatable_write);  // t's new metatable guards it in turn
  }
  lua_pushvalue(L, 2);
  lua_setmetatable(L, 1);
  if (type == LUA_TTABLE) guard_table(L, 2, &metatable_write);
  lua_settop(L, 1);
  return 1;
}

int LuaSandbox::check_pattern(lua_State* L) {
  LuaSandbox& s = of(L);
  const int ts = lua_type(L, 2), tp = lua_type(L, 3);
  if ((ts != LUA_TSTRING && ts != LUA_TNUMBER) || (tp != LUA_TSTRING && tp != LUA_TNUMBER)) return 0;
  size_t n = 0, m = 0;
  lua_tolstring(L, 2, &n);
  const char* p = lua_tolstring(L, 3, &m);
  const bool plain = lua_toboolean(L, 4) || std::none_of(p, p + m, [](char c) {
                       return std::strchr("^$*+?.([%-", c) != nullptr && c != '\0';
                     });
  // A plain search compares with memchr and memcmp: a byte is a fraction of an instruction.
  const double steps = plain ? double(n) * double(m) / kBytesPerInstruction : pattern_steps(n, p, m);
  if (steps > s.limits_.pattern_steps) {
    // No C++ object may be alive at lua_pushstring, which raises when memory is full, nor at
    // lua_error: the message is put together in a plain buffer first.
    char text[512];
    {
      const std::string where = location(L, 1);
      std::snprintf(text, sizeof text,
                    "%sstring.%s: this pattern over %zu bytes may take up to %.3g steps of backtracking (at most "
                    "%.3g): use fewer repetitions (*, +, -) or a shorter string",
                    where.c_str(), lua_tostring(L, 1), n, steps, s.limits_.pattern_steps);
    }
    lua_pushstring(L, text);
    return lua_error(L);
  }
  lua_settop(L, 3);
  return charge_text(L);
}

void LuaSandbox::open_libraries() {
  static constexpr luaL_Reg kLibraries[] = {{LUA_GNAME, luaopen_base},
                                            {LUA_STRLIBNAME, luaopen_string},
                                            {LUA_TABLIBNAME, luaopen_table},
                                            {LUA_MATHLIBNAME, luaopen_math},
                                            {LUA_UTF8LIBNAME, luaopen_utf8}};
  for (const luaL_Reg& lib : kLibraries) {
    luaL_requiref(L_, lib.name, lib.func, 1);
    lua_pop(L_, 1);
  }
  // What reads files or runs code from text, prints, or reaches under the sandbox.
  for (const char* name : {"dofile", "loadfile", "load", "print", "collectgarbage", "rawset", "require", "warn"}) {
    lua_pushnil(L_);
    lua_setglobal(L_, name);
  }
  // What a freeze of the script's state calls (push_library), taken before the script can
  // replace any of it: Lua's own next among them, which visits each key once in any order.
  lua_createtable(L_, 0, 8);
  for (const char* name : {"next", "type", "error", "rawget"}) {
    lua_getglobal(L_, name);
    lua_setfield(L_, -2, name);
  }
  lua_pushcfunction(L_, &LuaSandbox::ordered_pairs);
  lua_setfield(L_, -2, "pairs");
  lua_pushcfunction(L_, &LuaSandbox::plain_tostring);
  lua_setfield(L_, -2, "tostring");
  lua_getglobal(L_, LUA_STRLIBNAME);
  lua_getfield(L_, -1, "sub");
  lua_setfield(L_, -3, "sub");
  lua_pop(L_, 1);
  library_ = luaL_ref(L_, LUA_REGISTRYINDEX);
  // What would differ from run to run (lua_fixed_order.cpp): the order of next and pairs, the
  // addresses tostring shows.
  for (const luaL_Reg& f : {luaL_Reg{"next", &LuaSandbox::ordered_next}, luaL_Reg{"pairs", &LuaSandbox::ordered_pairs},
                            luaL_Reg{"tostring", &LuaSandbox::plain_tostring}}) {
    lua_pushcfunction(L_, f.func);
    lua_setglobal(L_, f.name);
  }
  lua_getglobal(L_, LUA_MATHLIBNAME);  // m:random is the module's generator; math's is not
  for (const char* name : {"random", "randomseed"}) {
    lua_pushnil(L_);
    lua_setfield(L_, -2, name);
  }
  lua_pop(L_, 1);
  // The script sees copies of string, table and utf8 with guards in them; the originals stay in
  // the registry, where Lua looks up a library function's name for its error messages.
  for (const char* name : {LUA_STRLIBNAME, LUA_TABLIBNAME, LUA_UTF8LIBNAME}) {
    lua_newtable(L_);
    lua_getglobal(L_, name);
    for (lua_pushnil(L_); lua_next(L_, -2);) {  // new, original, key, value
      lua_pushvalue(L_, -2);
      lua_insert(L_, -2);
      lua_rawset(L_, -5);  // leaves the key for lua_next
    }
    lua_pop(L_, 1);
    lua_setglobal(L_, name);
  }
  // Strings' metatable is shared by every string: its methods are the guarded copy, and it is
  // hidden, so that nothing can be kept in it.
  lua_pushliteral(L_, "");
  lua_getmetatable(L_, -1);
  lua_getglobal(L_, LUA_STRLIBNAME);
  lua_setfield(L_, -2, "__index");
  lua_pushboolean(L_, 0);
  lua_setfield(L_, -2, "__metatable");
  lua_pop(L_, 2);

  if (luaL_loadbufferx(L_, kGuards, std::strlen(kGuards), LuaSandbox::kHostChunk, "t") != LUA_OK) lua_error(L_);
  lua_pushglobaltable(L_);
  for (const char* name : {LUA_STRLIBNAME, LUA_TABLIBNAME, LUA_UTF8LIBNAME}) lua_getglobal(L_, name);
  lua_pushcfunction(L_, &LuaSandbox::charge);
  lua_pushcfunction(L_, &LuaSandbox::charge_text);
  for (lua_CFunction f : {&LuaSandbox::check_pattern, &LuaSandbox::buffered, &LuaSandbox::plain_concat,
                          &LuaSandbox::plain_format, &LuaSandbox::replaying})
    lua_pushcfunction(L_, f);
  // set_metatable's upvalue: the metatable a table gets when it becomes another's metatable.
  lua_createtable(L_, 0, 2);
  lua_pushcfunction(L_, &LuaSandbox::metatable_write);
  lua_setfield(L_, -2, "__newindex");
  lua_pushboolean(L_, 0);
  lua_setfield(L_, -2, "__metatable");
  lua_pushcclosure(L_, &LuaSandbox::set_metatable, 1);
  // The guards are dwatch's own code: only the memory for them can be missing.
  if (lua_pcall(L_, 12, 1, 0) != LUA_OK) lua_error(L_);
  guards_ = luaL_ref(L_, LUA_REGISTRYINDEX);
}

std::chrono::milliseconds LuaSandbox::tick() const { return limits_.patience.count() > 0 ? limits_.patience : 10ms; }

LuaWatchdog& LuaSandbox::watchdog() {
  if (!watchdog_) {
    own_watchdog_ = std::make_unique<LuaWatchdog>(tick());
    watchdog_ = own_watchdog_.get();
  }
  return *watchdog_;
}

LuaSandbox::Outcome LuaSandbox::call(int args, int results, bool counted) {
  executed_ = 0;
  stop_ = Stop::kNone;
  where_.clear();
  refused_size_ = 0;
  if (counted) lua_sethook(L_, &LuaSandbox::count_hook, LUA_MASKCOUNT, kHookEvery);
  else lua_sethook(L_, nullptr, 0, 0);
  LuaWatchdog& watchdog = this->watchdog();
  watchdog.begin(L_, counted ? uint32_t(std::max<int64_t>(1, limits_.deadline / tick())) : 1);
  // The message handler goes under the function and its arguments, and is taken away after.
  const int handler = lua_gettop(L_) - args;
  lua_pushcfunction(L_, &LuaSandbox::describe_error);
  lua_insert(L_, handler);
  in_call_ = true;
  const auto started = std::chrono::steady_clock::now();
  const int status = lua_pcall(L_, args, results, handler);
  const auto took = std::chrono::steady_clock::now() - started;
  in_call_ = false;
  lua_remove(L_, handler);
  watchdog.end();
  lua_sethook(L_, nullptr, 0, 0);
  if (limits_.pool && !limits_.pool->spend(std::chrono::duration_cast<std::chrono::nanoseconds>(took).count())) {
    lua_settop(L_, handler - 1);  // the call's results, or its error
    const std::string message = display_ + ": the run's Lua calls took more than " +
                                std::to_string(limits_.pool->seconds()) +
                                " s of wall-clock time together (--lua-seconds raises it)";
    lua_pushstring(L_, message.c_str());
    return Outcome::kFailed;
  }
  if (status == LUA_OK) return Outcome::kOk;
  // Lua's own "not enough memory" (a request refused while it collects, when it does not ask
  // again, caught and raised again by a guard) is the same stop as the memory found full: which
  // of the two a script meets depends on when the collector runs, not on the script.
  if (stop_ == Stop::kNone && lua_type(L_, -1) == LUA_TSTRING) {
    constexpr std::string_view kOutOfMemory = "not enough memory";
    const std::string_view text = lua_tostring(L_, -1);
    if (text.ends_with(kOutOfMemory)) stop_ = refused_why_;
  }
  // Uncounted, a stop says only that the call went far: the counted run decides, so that what a
  // call does never depends on the machine's speed.
  if (!counted && (stop_ != Stop::kNone || watchdog.interrupted())) {
    lua_pop(L_, 1);
    return Outcome::kInterrupted;
  }
  if (stop_ != Stop::kNone) {
    lua_pop(L_, 1);
    push_stop_message(stop_);
  } else if (watchdog.interrupted()) {
    lua_pop(L_, 1);
    const std::string message = display_ + ": ran for more than " + std::to_string(limits_.deadline.count()) +
                                " ms of wall-clock time in one call (work the instruction budget does not see)";
    lua_pushstring(L_, message.c_str());
  }
  return Outcome::kFailed;
}

// The message handler of a call: an error value that is not a string (`error(nil)`, `error({})`)
// carries no position, so it is described with the line it was raised at, found while that line
// is still on the stack. A string (which has its position when it needs one) and the limits' stop
// pass unchanged. No __tostring is called: that would be the script's code running in the handler.
int LuaSandbox::describe_error(lua_State* L) {
  if (lua_type(L, 1) == LUA_TSTRING || lua_touserdata(L, 1) == &kStopped) return 1;
  char text[LUA_IDSIZE + 96];
  {
    // Destroyed before Lua may raise (a memory error jumps over C++ frames).
    const std::string where = location(L, 1);
    std::snprintf(text, sizeof text, "%san error that is not a string (a %s value)", where.c_str(),
                  luaL_typename(L, 1));
  }
  lua_pushstring(L, text);
  return 1;
}

// A memory stop names the script but no line. Even in a state made for the call (a call run
// counted), which allocation meets the cap can move by a few: Lua draws a new seed for its string
// hashes in every state, and when a table with string keys grows follows their collisions.
void LuaSandbox::push_stop_message(Stop why) {
  const std::string message =
      why == Stop::kMemory ? display_ + ": not enough memory: a script's Lua state may hold at most " +
                                 sim::size_text(limits_.memory_bytes)
      : why == Stop::kPool
          ? display_ + ": not enough memory: the run's Lua states (one per script per stepping thread) may hold " +
                sim::size_text(limits_.pool->limit()) +
                " together, half of what this machine had available beyond the scenario's memory estimate"
          : (where_.empty() ? display_ + ": " : where_) + "ran more than " + std::to_string(limits_.instructions) +
                " instructions in one call (an endless loop?)";
  lua_pushstring(L_, message.c_str());
}

}  // namespace dw::scenarios
