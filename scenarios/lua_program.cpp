#include "scenarios/lua_program.h"

#include "scenarios/lua_sandbox.h"
#include "watch/lexer.h"

#include <lua.hpp>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <vector>

namespace dw::scenarios {
namespace {

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
constexpr const char* kFreeze = R"lua(
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
           LuaWatchdog* watchdog = nullptr)
      : sandbox_(display, limits, watchdog), L_(sandbox_.state()), display_(display), text_(text) {
    if (!L_) {
      error_ = display + ": no memory for a Lua state";
      return;
    }
    *static_cast<LuaState**>(lua_getextraspace(L_)) = this;
    if (luaL_loadbufferx(L_, text.data(), text.size(), ("@" + display).c_str(), "t") != LUA_OK || !call(0, 0)) {
      error_ = pop_message();
      return;
    }
  }
  LuaState(const LuaState&) = delete;
  LuaState& operator=(const LuaState&) = delete;

  const std::string& error() const { return error_; }

  // Reads `program`, `step` and `init` as the script defined them; false with error() set when
  // they are not as docs/design.md §11 says. Read raw, under a pcall: a script may have given its
  // globals or `program` a metatable, whose code must not run outside the limits.
  bool declare(Declared& d) {
    lua_pushcfunction(L_, &LuaState::read_declaration);
    lua_pushlightuserdata(L_, &d);
    if (!call(1, 0)) return failed();
    // The parameters in name order: Lua's next visits string keys in an order that differs
    // from run to run.
    std::sort(d.params.begin(), d.params.end());
    return true;
  }

  // Binds the module API and freezes the script (see kFreeze); false with error() set.
  bool prepare(const Declared& d) {
    declared_ = &d;
    auto index_table = [&](Names which, const std::vector<std::string>& names) {
      lua_newtable(L_);  // name -> index
      for (size_t i = 0; i < names.size(); ++i) {
        lua_pushinteger(L_, lua_Integer(i));
        lua_setfield(L_, -2, names[i].c_str());
        // The key's own string when Lua interns it (pushed twice, the same address), which the
        // table keeps alive; a longer name is looked up in the table.
        const char* once = lua_pushstring(L_, names[i].c_str());
        const char* twice = lua_pushstring(L_, names[i].c_str());
        names_[which].push_back(once == twice ? once : nullptr);
        lua_pop(L_, 2);
      }
      return lua_gettop(L_);
    };
    std::vector<std::string> param_names;
    for (const auto& [name, value] : d.params) {
      param_names.push_back(name);
      param_values_.push_back(value);
    }
    const int params = index_table(kParameters, param_names);
    const int vars = index_table(kVariables, d.vars);
    lua_pushglobaltable(L_);  // read raw, as declare read them
    lua_pushliteral(L_, "step");
    lua_rawget(L_, -2);
    step_ = luaL_ref(L_, LUA_REGISTRYINDEX);
    lua_pushliteral(L_, "init");
    lua_rawget(L_, -2);
    init_ = luaL_ref(L_, LUA_REGISTRYINDEX);
    lua_pop(L_, 1);

    // The module: one table, pointed at each module in turn. Its only own fields are id and step,
    // rewritten before every call, so nothing a script writes there outlives the call; the
    // methods sit behind its metatable, and a new field is an error. get and set find variables
    // in their upvalue, param the parameters in its own.
    lua_createtable(L_, 0, 2);
    for (const char* key : {"id", "step"}) {
      lua_pushstring(L_, key);
      lua_pushinteger(L_, 0);
      lua_rawset(L_, -3);
    }
    lua_createtable(L_, 0, 2);  // its metatable
    lua_createtable(L_, 0, 8);  // the methods
    static constexpr luaL_Reg kByVariable[] = {{"get", &LuaState::get}, {"set", &LuaState::set}, {nullptr, nullptr}};
    lua_pushvalue(L_, vars);
    luaL_setfuncs(L_, kByVariable, 1);
    lua_pushvalue(L_, params);
    lua_pushcclosure(L_, &LuaState::param, 1);
    lua_setfield(L_, -2, "param");
    // The tables m:inbox and m:neighbors hand out (their upvalues), and the metatable that lets
    // no entry be added to them.
    lua_createtable(L_, 0, 2);
    lua_pushcfunction(L_, &LuaState::new_entry);
    lua_setfield(L_, -2, "__newindex");
    lua_pushboolean(L_, 0);
    lua_setfield(L_, -2, "__metatable");
    read_only_ = luaL_ref(L_, LUA_REGISTRYINDEX);
    for (int pool = 0; pool < 3; ++pool) lua_newtable(L_);  // kLists, kMessages, kWords
    lua_pushvalue(L_, -3);
    lua_pushcclosure(L_, &LuaState::neighbors, 1);
    lua_setfield(L_, -5, "neighbors");
    lua_pushliteral(L_, "from");
    lua_pushliteral(L_, "data");
    lua_pushcclosure(L_, &LuaState::inbox, 5);
    lua_setfield(L_, -2, "inbox");
    static constexpr luaL_Reg kMethods[] = {
        {"send", &LuaState::send},         {"broadcast", &LuaState::broadcast}, {"random", &LuaState::random},
        {"position", &LuaState::position}, {"moving", &LuaState::moving},       {"move", &LuaState::move},
        {"pivot", &LuaState::pivot},       {"push", &LuaState::push},           {nullptr, nullptr}};
    luaL_setfuncs(L_, kMethods, 0);
    lua_setfield(L_, -2, "__index");
    lua_pushcfunction(L_, &LuaState::new_field);
    lua_setfield(L_, -2, "__newindex");
    lua_pushboolean(L_, 0);
    lua_setfield(L_, -2, "__metatable");
    lua_setmetatable(L_, -2);
    module_ = luaL_ref(L_, LUA_REGISTRYINDEX);
    lua_pop(L_, 2);  // params, vars

    luaL_requiref(L_, LUA_DBLIBNAME, luaopen_debug, 0);  // for kFreeze only: never a global
    const int debug = lua_gettop(L_);
    if (luaL_loadbufferx(L_, kFreeze, std::strlen(kFreeze), "=dwatch", "t") != LUA_OK) return failed();
    sandbox_.push_library();
    lua_setupvalue(L_, -2, 1);  // the chunk's _ENV
    lua_pushglobaltable(L_);
    lua_pushvalue(L_, debug);
    sandbox_.push_guards();
    if (!call(3, 2)) return failed();
    const auto quadruples = static_cast<lua_Integer>(lua_tointeger(L_, -1));
    lua_pop(L_, 1);
    // What every call needs stays on the stack: the module table, the keys of its fields, and
    // for each upvalue to check its function and its value (kFreeze's quadruples).
    lua_remove(L_, debug);
    const int checks = lua_gettop(L_);  // the stack's only entry, removed when the slots above are made
    luaL_checkstack(L_, int(quadruples) + 8, "upvalues to check");
    lua_rawgeti(L_, LUA_REGISTRYINDEX, module_);
    lua_pushliteral(L_, "id");
    lua_pushliteral(L_, "step");
    // Per check: its holder, then (a metamethod's) its key, then the value it had.
    for (lua_Integer i = 1; i + 3 <= quadruples; i += 4) {
      lua_rawgeti(L_, checks, i);
      Check check{lua_type(L_, -1) == LUA_TTABLE, 0, {}, lua_gettop(L_)};
      lua_rawgeti(L_, checks, i + 1);
      if (check.field) check.name = lua_tostring(L_, -1);
      else check.index = int(lua_tointeger(L_, -1)), lua_pop(L_, 1);
      lua_rawgeti(L_, checks, i + 2);
      if (!check.field) check.name = lua_tostring(L_, -1);
      lua_pop(L_, 1);
      lua_rawgeti(L_, checks, i + 3);
      checks_.push_back(std::move(check));
    }
    lua_remove(L_, checks);
    for (Check& check : checks_) --check.slot;  // the table of checks below them is gone
    saved_.resize(d.vars.size());
    return true;
  }

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
  void run(sim::ModuleContext& m, bool initializing, bool after_init = false) {
    std::string message;
    if (sandbox_.limits().patience.count() == 0) {
      message = run_counted(m, initializing, after_init);
    } else {
      // What the call does goes into the module's variables and its outbox: kept, to take back
      // if the watchdog interrupts it and it runs again, counted.
      const sim::ModuleContext::Sent sent = m.sent();
      for (size_t v = 0; v < saved_.size(); ++v) saved_[v] = m.assigned(uint32_t(v));
      std::optional<std::string> finished = run_here(m, initializing, after_init, false);
      if (!finished || !finished->empty()) {
        for (size_t v = 0; v < saved_.size(); ++v) m.set(uint32_t(v), saved_[v]);
        m.take_back(sent);
        // What the interrupted try left is garbage: gone before a second state is made.
        lua_gc(L_, LUA_GCCOLLECT);
        finished = run_counted(m, initializing, after_init);
      }
      message = std::move(*finished);
    }
    if (!message.empty()) m.fail("at step " + std::to_string(m.step()) + ": " + message);
  }

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

  // The call run counted in a fresh state, made from the script as this one was (its own watchdog
  // lent, so that no thread is started): the message of its failure, empty when it went through.
  std::string run_counted(sim::ModuleContext& m, bool initializing, bool after_init) {
    LuaState fresh(display_, text_, sandbox_.limits(), &sandbox_.watchdog());
    if (fresh.error().empty()) fresh.prepare(*declared_);
    if (!fresh.error().empty()) return fresh.error();
    return *fresh.run_here(m, initializing, after_init, true);
  }

  // The call run in this state, counted or not: the message of its failure, empty when it went
  // through, nothing when it was uncounted and interrupted.
  std::optional<std::string> run_here(sim::ModuleContext& m, bool initializing, bool after_init, bool counted) {
    module_context_ = &m;
    after_init_ = after_init;
    const LuaSandbox::Outcome outcome = attempt(initializing ? init_ : step_, counted);
    module_context_ = nullptr;
    if (outcome == LuaSandbox::Outcome::kInterrupted) return std::nullopt;
    if (outcome == LuaSandbox::Outcome::kFailed) return pop_message();
    if (const Check* changed = changed_check())
      return display_ + ": " + (initializing ? "init" : "step") + " wrote " +
             (changed->field ? "'" + changed->name + "' of a table made when the script loaded"
                             : "the local '" + changed->name + "' declared outside it") +
             ": a script keeps its state in its variables (m:set), which a rollback restores";
    return std::string();
  }

  // One try of a call of init or step (the registry's `function`) on the module, with every
  // instruction counted or under the watchdog; the error stays on the stack when it fails.
  LuaSandbox::Outcome attempt(int function, bool counted) {
    // Everything a try may have changed starts afresh (a script may write m.id or m.step).
    draws_ = 0;
    messages_ = 0;
    for (Pool& pool : pools_) pool.handed_out = 0;
    lua_pushvalue(L_, kIdKey);
    lua_pushinteger(L_, module_context_->id());
    lua_rawset(L_, kModuleSlot);
    lua_pushvalue(L_, kStepKey);
    lua_pushinteger(L_, module_context_->step());
    lua_rawset(L_, kModuleSlot);
    lua_rawgeti(L_, LUA_REGISTRYINDEX, function);
    lua_pushvalue(L_, kModuleSlot);
    return sandbox_.call(1, 0, counted);
  }

  // A counted pcall; the error message stays on the stack when false.
  bool call(int args, int results) { return sandbox_.call(args, results, true) == LuaSandbox::Outcome::kOk; }
  std::string pop_message() {
    std::string message = lua_type(L_, -1) == LUA_TSTRING ? lua_tostring(L_, -1) : "an error that is not a string";
    lua_pop(L_, 1);
    return message;
  }
  bool failed() {
    error_ = pop_message();
    return false;
  }

  // The check (an upvalue, a frozen table's metamethod) whose value a call changed, or nullptr.
  const Check* changed_check() {
    for (const Check& check : checks_) {
      if (check.field) {
        lua_pushvalue(L_, check.slot + 1);
        lua_rawget(L_, check.slot);
      } else {
        lua_getupvalue(L_, check.slot, check.index);
      }
      const bool same = lua_rawequal(L_, -1, check.slot + (check.field ? 2 : 1));
      lua_pop(L_, 1);
      if (!same) return &check;
    }
    return nullptr;
  }

  // read_declaration(declared): declare's reads, each raw. An error is the message to report.
  static int read_declaration(lua_State* L) {
    Declared& d = *static_cast<Declared*>(lua_touserdata(L, 1));
    const char* display = of(L).display_.c_str();
    auto fail = [&](const char* why) -> int {
      lua_pushfstring(L, "%s: %s", display, why);
      return lua_error(L);
    };
    lua_pushglobaltable(L);  // 2
    lua_pushliteral(L, "program");
    if (lua_rawget(L, 2) != LUA_TTABLE) return fail("the script must set `program = { vars = {...} }`");  // 3
    lua_pushliteral(L, "vars");
    if (lua_rawget(L, 3) != LUA_TTABLE) return fail("`program.vars` must be a list of variable names");  // 4
    for (lua_Integer i = 1; lua_rawgeti(L, 4, i) != LUA_TNIL; ++i) {
      if (lua_type(L, -1) != LUA_TSTRING) return fail("`program.vars` must list names (strings)");
      size_t length = 0;
      const char* name = lua_tolstring(L, -1, &length);
      if (!watch::is_name(std::string_view(name, length))) {
        lua_pushfstring(L, "%s: `program.vars` lists \"", display);
        lua_pushlstring(L, name, std::min<size_t>(length, 80));
        lua_pushfstring(L,
                        "\", which a watchpoint cannot name: letters, digits and _, not starting with a digit, at "
                        "most %d of them, and none of and, or, not, modules, neighbor, last, next",
                        int(watch::kMaxNameLength));
        lua_concat(L, 3);
        return lua_error(L);
      }
      d.vars.emplace_back(name, length);
      lua_pop(L, 1);
    }
    lua_pop(L, 2);  // nil, vars
    lua_pushliteral(L, "params");
    if (lua_rawget(L, 3) != LUA_TNIL) {  // 4
      if (!lua_istable(L, 4)) return fail("`program.params` must be a table of names and default integers");
      for (lua_pushnil(L); lua_next(L, 4); lua_pop(L, 1)) {
        int ok = 0;
        const lua_Integer v = lua_tointegerx(L, -1, &ok);
        if (lua_type(L, -2) != LUA_TSTRING || !ok || lua_type(L, -1) != LUA_TNUMBER)
          return fail("`program.params` must map names to integers");
        size_t length = 0;
        const char* name = lua_tolstring(L, -2, &length);
        d.params.emplace_back(std::string(name, length), v);
      }
    }
    lua_pushliteral(L, "step");
    if (lua_rawget(L, 2) != LUA_TFUNCTION) return fail("the script must define `function step(m)`");
    lua_pushliteral(L, "init");
    const int init = lua_rawget(L, 2);
    if (init != LUA_TNIL && init != LUA_TFUNCTION) return fail("`init` must be a function (init(m)) or absent");
    d.has_init = init == LUA_TFUNCTION;
    return 0;
  }

  static int new_field(lua_State* L) {
    return luaL_error(L, "sets m.%s: the module has no such field (a script keeps its state with m:set)",
                      luaL_tolstring(L, 2, nullptr));
  }

  // The index of the variable (kVariables) or parameter (kParameters) named by argument 2. Names
  // of up to 40 bytes are interned by Lua: the string passed is the very one the table of names
  // holds (which keeps it alive), so comparing addresses finds it; the upvalue table looks up the
  // rest, and reports a name that is neither.
  enum Names { kVariables, kParameters };
  static uint32_t lookup(lua_State* L, Names which) {
    const std::vector<const char*>& names = of(L).names_[which];
    if (const char* name = lua_tolstring(L, 2, nullptr))
      for (size_t i = 0; i < names.size(); ++i)
        if (names[i] == name) return uint32_t(i);
    lua_pushvalue(L, 2);
    if (lua_rawget(L, lua_upvalueindex(1)) != LUA_TNUMBER)
      luaL_error(L,
                 which == kVariables ? "'%s' is not a variable of this program (declare it in program.vars)"
                                     : "'%s' is not a parameter of this program (declare it in program.params)",
                 luaL_checkstring(L, 2));
    const auto index = static_cast<uint32_t>(lua_tointeger(L, -1));
    lua_pop(L, 1);
    return index;
  }

  static int64_t integer(lua_State* L, int arg, const char* what) {
    if (lua_isinteger(L, arg)) return lua_tointeger(L, arg);
    int ok = 0;  // a float with an integral value, or not a number at all
    const lua_Integer v = lua_tointegerx(L, arg, &ok);
    if (!ok || lua_type(L, arg) != LUA_TNUMBER)
      luaL_error(L, "%s must be an integer, not %s", what,
                 lua_type(L, arg) == LUA_TNUMBER ? lua_tostring(L, arg) : luaL_typename(L, arg));
    return v;
  }

  static int get(lua_State* L) {
    const uint32_t v = lookup(L, kVariables);
    // At step 0, after init, what init set stands for the values before the step.
    lua_pushinteger(L, of(L).after_init_ ? module(L).assigned(v) : module(L).get(v));
    return 1;
  }
  static int set(lua_State* L) {
    const uint32_t v = lookup(L, kVariables);
    module(L).set(v, integer(L, 3, "a variable's value"));
    return 0;
  }
  static int new_entry(lua_State* L) {
    return luaL_error(L, "adds '%s' to a table of m:inbox() or m:neighbors(), which are the step's own (copy it first)",
                      luaL_tolstring(L, 2, nullptr));
  }

  // Tables handed out by m:inbox and m:neighbors, kept from call to call instead of garbage
  // made per module: what a script got from a pool may have been changed, never kept (its state
  // lives in its variables). Lists and words are arrays, messages have the fields from and data.
  // The pools are the methods' upvalues (kLists, kMessages, kWords), in this order.
  enum PoolKind { kLists, kMessages, kWords };
  struct Pool {
    std::vector<uint32_t> filled;  // entries written into each table
    uint32_t handed_out = 0;       // tables handed out in this call
  };

  // A table of the pool at `upvalue` for this call at the top of the stack, holding `size`
  // entries: those from 1 to `size` are the caller's to fill, the ones after are cleared here.
  void take_table(lua_State* L, PoolKind kind, int upvalue, uint32_t size) {
    Pool& pool = pools_[kind];
    const uint32_t slot = pool.handed_out++;
    if (slot == pool.filled.size()) {
      lua_createtable(L, kind == kMessages ? 0 : int(std::max(size, 8u)), kind == kMessages ? 2 : 0);
      lua_rawgeti(L, LUA_REGISTRYINDEX, read_only_);
      lua_setmetatable(L, -2);
      lua_pushvalue(L, -1);
      lua_rawseti(L, lua_upvalueindex(upvalue), lua_Integer(slot) + 1);
      pool.filled.push_back(0);
    } else {
      lua_rawgeti(L, lua_upvalueindex(upvalue), lua_Integer(slot) + 1);
      for (uint32_t i = size; i < pool.filled[slot]; ++i) {
        lua_pushnil(L);
        lua_rawseti(L, -2, lua_Integer(i) + 1);
      }
    }
    pool.filled[slot] = size;
  }

  static int neighbors(lua_State* L) {
    const auto n = module(L).neighbors();
    of(L).take_table(L, kLists, 1, uint32_t(n.size()));
    for (size_t i = 0; i < n.size(); ++i) {
      lua_pushinteger(L, n[i]);
      lua_rawseti(L, -2, lua_Integer(i + 1));
    }
    return 1;
  }
  // { { from = id, data = { words } }, ... }. Upvalues: the three pools, "from" and "data".
  static int inbox(lua_State* L) {
    LuaState& s = of(L);
    const auto in = module(L).inbox();
    s.take_table(L, kLists, 1, uint32_t(in.size()));
    for (size_t i = 0; i < in.size(); ++i) {
      s.take_table(L, kMessages, 2, 0);
      lua_pushvalue(L, lua_upvalueindex(4));
      lua_pushinteger(L, in[i].from);
      lua_rawset(L, -3);
      const auto words = in[i].payload();
      lua_pushvalue(L, lua_upvalueindex(5));
      s.take_table(L, kWords, 3, uint32_t(words.size()));
      for (size_t w = 0; w < words.size(); ++w) {
        lua_pushinteger(L, words[w]);
        lua_rawseti(L, -2, lua_Integer(w + 1));
      }
      lua_rawset(L, -3);
      lua_rawseti(L, -2, lua_Integer(i + 1));
    }
    return 1;
  }

  // The words of a message: a list of integers, at most Message::kMaxWords. Trivially
  // destructible, as everything alive where a Lua error may jump.
  struct Payload {
    std::array<int64_t, sim::Message::kMaxWords> words;
    size_t size;
    std::span<const int64_t> span() const { return {words.data(), size}; }
  };
  static Payload payload(lua_State* L, int arg) {
    luaL_checktype(L, arg, LUA_TTABLE);
    const auto n = static_cast<lua_Integer>(lua_rawlen(L, arg));
    if (n > lua_Integer(sim::Message::kMaxWords))
      luaL_error(L, "a message holds at most %d integers, not %I", int(sim::Message::kMaxWords), n);
    Payload p{{}, static_cast<size_t>(n)};
    const int top = lua_gettop(L);
    for (lua_Integer i = 1; i <= n; ++i) lua_rawgeti(L, arg, i);
    for (int i = 0; i < int(n); ++i) p.words[size_t(i)] = integer(L, top + 1 + i, "a message word");
    lua_settop(L, top);
    return p;
  }
  static int send(lua_State* L) {
    sim::ModuleContext& m = module(L);
    const int64_t to = integer(L, 2, "the module sent to");
    if (to < 0 || to > int64_t(UINT32_MAX) || !m.is_neighbor(sim::ModuleId(to)))
      luaL_error(L, "module %d sent to %I, which is not its neighbour", int(m.id()), lua_Integer(to));
    const Payload words = payload(L, 3);
    count_messages(L, "send", 1);
    m.send(sim::ModuleId(to), words.span());
    return 0;
  }
  static int broadcast(lua_State* L) {
    const Payload words = payload(L, 2);
    sim::ModuleContext& m = module(L);
    count_messages(L, "broadcast", m.neighbors().size());
    m.broadcast(words.span());
    return 0;
  }
  // Counts `n` more messages of this call against the limit, or raises the error.
  static void count_messages(lua_State* L, const char* method, size_t n) {
    LuaState& s = of(L);
    const uint32_t limit = s.sandbox_.limits().messages;
    if (n > limit - std::min(s.messages_, limit))
      luaL_error(L, "m:%s: this call would send more than %d messages, the limit of one call of init or step", method,
                 int(limit));
    s.messages_ += uint32_t(n);
  }
  // m:random(n): 0 .. n - 1; m:random(0): 64 random bits (as Lua's math.random(0)). Each draw of
  // a step reads its own stream, the first stream 0.
  static int random(lua_State* L) {
    const int64_t n = integer(L, 2, "the bound of m:random(n)");
    if (n < 0) luaL_error(L, "m:random(n) needs n >= 1 (or 0 for 64 bits), not %I", lua_Integer(n));
    sim::ModuleContext& m = module(L);
    const uint32_t stream = of(L).draws_++;
    lua_pushinteger(L, n == 0 ? static_cast<lua_Integer>(m.random(stream)) : m.uniform(n, stream));
    return 1;
  }
  // The body (docs/design.md §11, mirroring sim::ModuleContext's sensing and actuation): only in a world
  // with bodies, which the scenario's [physics] makes.
  static sim::ModuleContext& body(lua_State* L, const char* method) {
    sim::ModuleContext& m = module(L);
    if (!m.has_body())
      luaL_error(L, "m:%s() needs a body, and this world has none (the scenario's [physics] is off)", method);
    return m;
  }
  static sim::Vec3 vector(lua_State* L) {  // arguments 2, 3 and 4
    sim::Vec3 v;
    for (int i = 0; i < 3; ++i) v[size_t(i)] = float(luaL_checknumber(L, 2 + i));
    return v;
  }
  // m:position(): x, y, z of the body's centre as the step began, in module sizes.
  static int position(lua_State* L) {
    const sim::Vec3& p = body(L, "position").pose().position;
    for (float c : p) lua_pushnumber(L, c);
    return 3;
  }
  // m:moving(): whether a lattice move of the module is under way.
  static int moving(lua_State* L) {
    lua_pushboolean(L, body(L, "moving").moving());
    return 1;
  }
  // m:move(dx, dy, dz): a lattice move by one module size into a free cell, carried out as the
  // world steps on (refused when the cell is taken or the module is already moving).
  static int move(lua_State* L) {
    sim::ModuleContext& m = body(L, "move");
    m.move(vector(L));
    return 0;
  }
  // m:pivot(about, dx, dy, dz): a pivot about the neighbour `about` into the cell at (dx, dy, dz)
  // from this one (a cube about the edge they share, a sphere rolling over it); a taken cell or a
  // blocked sweep is a program error.
  static int pivot(lua_State* L) {
    sim::ModuleContext& m = body(L, "pivot");
    const int64_t about = integer(L, 2, "the module pivoted about");
    sim::Vec3 offset;
    for (int i = 0; i < 3; ++i) offset[size_t(i)] = float(luaL_checknumber(L, 3 + i));
    if (about < 0 || about > int64_t(UINT32_MAX) || !m.is_neighbor(sim::ModuleId(about)))
      luaL_error(L, "module %d pivots about %I, which is not its neighbour", int(m.id()), lua_Integer(about));
    m.pivot(sim::ModuleId(about), offset);
    return 0;
  }
  // m:push(x, y, z): an impulse on the body, applied as the world steps on.
  static int push(lua_State* L) {
    sim::ModuleContext& m = body(L, "push");
    m.push(vector(L));
    return 0;
  }

  static int param(lua_State* L) {
    lua_pushinteger(L, of(L).param_values_[lookup(L, kParameters)]);
    return 1;
  }

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

class LuaProgram final : public sim::HostProgram {
 public:
  LuaProgram(std::string display, std::string text, Declared declared, LuaLimits limits)
      : display_(std::move(display)), text_(std::move(text)), declared_(std::move(declared)), limits_(limits) {}

  std::string_view name() const override { return display_; }
  std::vector<sim::VariableSpec> variables() const override {
    std::vector<sim::VariableSpec> out;
    for (const std::string& v : declared_.vars) out.push_back({v, 0});
    return out;
  }
  void step(sim::ModuleContext& m) const override {
    auto& s = static_cast<LuaState&>(*m.scratch());
    if (!s.error().empty()) {
      m.fail("at step " + std::to_string(m.step()) + ": " + s.error());
      return;
    }
    if (m.step() == 0 && declared_.has_init) s.run(m, true);
    s.run(m, false, m.step() == 0 && declared_.has_init);
  }
  // A stepping thread's own Lua state, declared from what the script declared at load.
  std::unique_ptr<sim::ProgramScratch> make_scratch() const override {
    auto s = std::make_unique<LuaState>(display_, text_, limits_);
    if (s->error().empty()) s->prepare(declared_);
    return s;
  }

 private:
  std::string display_, text_;
  Declared declared_;
  LuaLimits limits_;
};

}  // namespace

namespace {

// What the script declares, checked by loading it once; nothing, with the reason in `why`.
std::optional<Declared> declared_by(const std::string& display, const std::string& text, std::string& why,
                                    const LuaLimits& limits) {
  LuaState probe(display, text, limits);
  Declared declared;
  if (!probe.error().empty() || !probe.declare(declared) || !probe.prepare(declared)) {
    why = probe.error();
    return std::nullopt;
  }
  return declared;
}

}  // namespace

std::unique_ptr<const sim::HostProgram> make_lua_program(const std::string& display, const std::string& text,
                                                         TableReader& params, std::string& why, const LuaLimits& limits,
                                                         ParamValues* given) {
  std::optional<Declared> declared = declared_by(display, text, why, limits);
  if (!declared) return nullptr;
  bool ok = true;
  for (auto& [name, value] : declared->params)
    if (params.has(name)) {
      const auto v = params.integer(name, INT64_MIN, INT64_MAX);
      if (v) value = *v;
      else ok = false;
      if (v && given) given->emplace_back(name, *v);
    }
  if (!ok) return nullptr;
  return std::make_unique<LuaProgram>(display, text, std::move(*declared), limits);
}

std::unique_ptr<const sim::HostProgram> make_lua_program(const std::string& display, const std::string& text,
                                                         const ParamValues& given, std::string& why,
                                                         const LuaLimits& limits) {
  std::optional<Declared> declared = declared_by(display, text, why, limits);
  if (!declared) return nullptr;
  for (const auto& param : given) {
    auto it = std::find_if(declared->params.begin(), declared->params.end(),
                           [&](const auto& p) { return p.first == param.first; });
    if (it == declared->params.end()) {
      why =
          display + ": the scenario sets '" + param.first + "', which the script no longer declares in program.params";
      return nullptr;
    }
    it->second = param.second;
  }
  return std::make_unique<LuaProgram>(display, text, std::move(*declared), limits);
}

}  // namespace dw::scenarios
