// One Lua state of a host program in Lua (scenarios/lua_host/lua_program.h): the script loaded into it,
// sandboxed (scenarios/lua_host/lua_sandbox.h) and frozen, and the module `m` its calls of init and step
// are given. Internal to scenarios/: lua_state.cpp loads, declares, freezes and runs the script,
// lua_module_api.cpp holds the functions the script calls on `m`, lua_program.cpp makes a
// program of it with one state per stepping thread.
#pragma once

#include <lua.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "scenarios/lua_host/lua_sandbox.h"
#include "sim/host_program.h"

namespace dw::scenarios {

// Run once in every Lua state after the script: freezes the globals and every table reached from
// them, from a function's upvalues or from a table's metatable, and lists what to check after
// each call as {holder, key, name, value} quadruples: a function's upvalue (holder a function, key
// its index) or a metamethod of a frozen table (holder the table, key its name). Locals of the
// script (`local n = 0` outside step) are upvalues: writing one keeps state outside the module's
// variables, which a rollback could not restore. The sandbox's guards keep nothing and are
// skipped.
//
// A frozen table is emptied and its contents moved behind a read-only metatable (__index reads
// them, __newindex refuses, __len and __pairs list them). Its metamethods (keys "__...") stay in
// it, since Lua looks them up raw when the table is another's metatable (a class: `C.__index = C`);
// writing one is found by the checks. A metatable the table had keeps its metamethods: they are
// copied into the new one, its __index is asked for what the contents lack, and its __len and
// __pairs are given the contents.
//
// The chunk's _ENV is the sandbox's library as it was before the script ran (push_library): a
// script that replaced `next` or `type` cannot change how it is frozen.
inline constexpr const char* kFreeze = R"lua(
local G, debug, guards = ...
local getmetatable, setmetatable = debug.getmetatable, debug.setmetatable
local frozen, seen, checks, count = {}, {}, {}, 0
for _, f in next, guards do seen[f] = true end
local function deny(_, k)
  error("writes '" .. tostring(k) .. "' outside the module's variables (a script keeps its state with m:set)", 2)
end
local function check(holder, key, name, value)  -- counted: a value may be nil
  checks[count + 1], checks[count + 2], checks[count + 3], checks[count + 4] = holder, key, name, value
  count = count + 4
end
local freeze_value
local function freeze(t)
  if frozen[t] then return end
  frozen[t] = true
  local own = getmetatable(t)
  local hidden, kept = {}, {}
  for k, v in next, t do
    if type(k) == "string" and sub(k, 1, 2) == "__" then kept[k] = v else hidden[k] = v end
  end
  for k in next, hidden do t[k] = nil end
  local mt = {}
  if own ~= nil then
    for k, v in next, own do mt[k] = v end
    if rawget(own, "__index") ~= nil then setmetatable(hidden, { __index = rawget(own, "__index") }) end
  end
  mt.__index, mt.__newindex = hidden, deny
  -- Its own __len and __pairs count and list the contents: they are given them, not t.
  local own_len, own_pairs = mt.__len, mt.__pairs
  mt.__len = own_len and function() return own_len(hidden) end or function() return #hidden end
  mt.__pairs = own_pairs and function() return own_pairs(hidden) end or function() return pairs(hidden) end
  if rawget(mt, "__metatable") == nil then mt.__metatable = false end
  setmetatable(t, mt)
  for _, v in next, hidden do freeze_value(v) end
  for k, v in next, kept do
    freeze_value(v)
    check(t, k, k, v)
  end
  if own ~= nil then freeze_value(own) end
end
function freeze_value(v)
  if type(v) == "table" then
    freeze(v)
  elseif type(v) == "function" and not seen[v] and debug.getinfo(v, "S").what ~= "C" then
    seen[v] = true
    local i = 1
    while true do
      local name, value = debug.getupvalue(v, i)
      if name == nil then break end
      if name ~= "_ENV" then
        freeze_value(value)
        check(v, i, name, value)
      end
      i = i + 1
    end
  end
end
freeze(G)
return checks, count
)lua";

// What the script declares of itself (read from its `program` table when it is loaded).
struct Declared {
  std::vector<std::string> vars;
  std::vector<std::pair<std::string, int64_t>> params;  // with their values for this scenario
  bool has_init = false;
};

// One Lua state: the script loaded into it, sandboxed and frozen; a stepping thread's scratch.
class LuaState final : public sim::ProgramScratch {
 public:
  // `watchdog`: one of the same thread to lend the state (see run_counted).
  LuaState(const std::string& display, const std::string& text, const LuaLimits& limits,
           LuaWatchdog* watchdog = nullptr);
  LuaState(const LuaState&) = delete;
  LuaState& operator=(const LuaState&) = delete;

  const std::string& error() const { return error_; }

  // Reads `program`, `step` and `init` as the script defined them; false with error() set when
  // they are not as docs/design.md §11 says. Read raw, under a pcall: a script may have given its
  // globals or `program` a metatable, whose code must not run outside the limits.
  bool declare(Declared& d);

  // Binds the module API and freezes the script (see kFreeze); false with error() set.
  bool prepare(const Declared& d);

  // Runs init (when `initializing`) or step for one module. When the script fails, the module's
  // error says where: the script's file:line, the module and the step.
  //
  // A call runs first uncounted in this state. One that goes through is kept; one that runs past
  // its patience, meets a limit or fails is taken back and run again counted, in a state of its
  // own made for that call (`run_counted`). A failure is run again because its message depends on
  // the hook: Lua saves an instruction's position only when a hook runs or the instruction may
  // call out, so an error raised inside the VM with no hook (an integer `n % 0`) names the line of
  // the last saved instruction, which the counted run, saving each one, does not.
  //
  // A long-lived state keeps what earlier calls grew (Lua's stack, its call records and string
  // table, uncollected garbage), and where a call meets the memory cap moves with them, so the
  // counted run, which alone decides whether a call stops and why, starts from the same state
  // every time: the same script on the same variables stops at the same place, whatever ran
  // before, on any machine and thread count (but for the memory cap's allocation or two that
  // Lua's hash seed moves, lua_sandbox.cpp).
  void run(sim::ModuleContext& m, bool initializing, bool after_init = false);

 private:
  // Stack slots of the state's own thread, between calls (prepare pushes them).
  // The checks' slots follow them (Check::slot).
  static constexpr int kModuleSlot = 1, kIdKey = 2, kStepKey = 3;
  // What a call must leave as it was (see kFreeze).
  struct Check {
    bool field;  // a frozen table's metamethod, else a function's upvalue
    int index;   // of the upvalue in its function
    std::string name;
    int slot;  // on the stack: the function or table, (a metamethod's) key, the value
  };

  static LuaState& of(lua_State* L) { return **static_cast<LuaState**>(lua_getextraspace(L)); }
  static sim::ModuleContext& module(lua_State* L) {
    LuaState& s = of(L);
    if (!s.module_context_) luaL_error(L, "the module is only there while init or step runs");
    return *s.module_context_;
  }

  // Loading and running (lua_state.cpp).
  std::string run_counted(sim::ModuleContext& m, bool initializing, bool after_init);
  std::optional<std::string> run_here(sim::ModuleContext& m, bool initializing, bool after_init, bool counted);
  LuaSandbox::Outcome attempt(int function, bool counted);
  bool call(int args, int results);
  std::string pop_message();
  bool failed();
  const Check* changed_check();
  static int read_declaration(lua_State* L);
  static int bind_host(lua_State* L);

  // The module API the script calls on `m` (lua_module_api.cpp).
  static int new_field(lua_State* L);
  enum Names { kVariables, kParameters };  // which names lookup reads
  static uint32_t lookup(lua_State* L, Names which);
  static int64_t integer(lua_State* L, int arg, const char* what);
  static int get(lua_State* L);
  static int set(lua_State* L);
  static int new_entry(lua_State* L);

  // Tables handed out by m:inbox and m:neighbors, kept from call to call instead of garbage
  // made per module: what a script got from a pool may have been changed, never kept (its state
  // lives in its variables). Lists and words are arrays, messages have the fields from and data.
  // The pools are the methods' upvalues (kLists, kMessages, kWords), in this order.
  enum PoolKind { kLists, kMessages, kWords };
  struct Pool {
    std::vector<uint32_t> filled;  // entries written into each table
    uint32_t handed_out = 0;       // tables handed out in this call
  };
  void take_table(lua_State* L, PoolKind kind, int upvalue, uint32_t size);
  static int neighbors(lua_State* L);
  static int inbox(lua_State* L);
  struct Payload;  // the words of a message
  static Payload payload(lua_State* L, int arg);
  static int send(lua_State* L);
  static int broadcast(lua_State* L);
  static void count_messages(lua_State* L, const char* method, size_t n);
  static int random(lua_State* L);
  static sim::ModuleContext& body(lua_State* L, const char* method);
  static sim::Vec3 vector(lua_State* L, const char* method);
  static int position(lua_State* L);
  static int moving(lua_State* L);
  static int move(lua_State* L);
  static int pivot(lua_State* L);
  static int push(lua_State* L);
  static int param(lua_State* L);

  LuaSandbox sandbox_;
  lua_State* L_ = nullptr;
  std::string display_, error_;
  const std::string& text_;             // the script's, kept by its program
  const Declared* declared_ = nullptr;  // what prepare bound, kept by the program
  int step_ = LUA_NOREF, init_ = LUA_NOREF, module_ = LUA_NOREF, read_only_ = LUA_NOREF;
  std::vector<Check> checks_;  // their slots are on the stack above kStepKey
  std::array<Pool, 3> pools_;
  std::array<std::vector<const char*>, 2> names_;  // of the variables and the parameters (see lookup)
  std::vector<int64_t> param_values_;
  std::vector<int64_t> saved_;  // the variables before a call, to take back
  sim::ModuleContext* module_context_ = nullptr;
  bool after_init_ = false;  // step 0 of a script with init: m:get reads what init set
  uint32_t draws_ = 0;
  uint32_t messages_ = 0;  // sent by this call (count_messages)
};

}  // namespace dw::scenarios
