// A LuaState's own work (lua_state.h): loading the script, reading what it declares, binding the
// module API and freezing the script (kFreeze), and running a call of init or step, uncounted
// first and, when that does not go through, counted in a fresh state.
#include "scenarios/lua_host/lua_state.h"

#include "watch/lexer.h"

#include <algorithm>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

namespace dw::scenarios {

LuaState::LuaState(const std::string& display, const std::string& text, const LuaLimits& limits, LuaWatchdog* watchdog)
    : sandbox_(display, limits, watchdog), L_(sandbox_.state()), display_(display), text_(text) {
  if (!L_) {
    error_ = display + ": no memory for a Lua state";
    return;
  }
  *static_cast<LuaState**>(lua_getextraspace(L_)) = this;
  const int loaded = luaL_loadbufferx(L_, text.data(), text.size(), ("@" + display).c_str(), "t");
  if (loaded == LUA_ERRSYNTAX && !display.ends_with(".lua")) {
    // A path may name any file (a key, a password file): its syntax error would quote it ("near
    // '"hunter2-secret...'"). A file that is no .lua script is said to be no Lua, quoting nothing.
    lua_pop(L_, 1);
    error_ = display + ": not Lua source (a script is a .lua file; nothing of this one is shown)";
    return;
  }
  if (loaded != LUA_OK || !call(0, 0)) {
    error_ = pop_message();
    return;
  }
}

bool LuaState::declare(Declared& d) {
  lua_pushcfunction(L_, &LuaState::read_declaration);
  lua_pushlightuserdata(L_, &d);
  if (!call(1, 0)) return failed();
  // The parameters in name order: Lua's next visits string keys in an order that differs
  // from run to run.
  std::sort(d.params.begin(), d.params.end());
  return true;
}

// bind_host(): the module table, its methods and metatable, and the name tables behind get, set
// and param, made under a protected call: their size follows the script's declaration, so they
// may meet the memory cap, which must then be an error, not Lua's panic.
int LuaState::bind_host(lua_State* L) {
  LuaState& self = of(L);
  // Nothing here owns memory a Lua error, unwinding past it, would leave behind.
  auto index_table = [&](Names which, size_t count, auto name_of) {
    lua_newtable(L);  // name -> index
    for (size_t i = 0; i < count; ++i) {
      const char* name = name_of(i);
      lua_pushinteger(L, lua_Integer(i));
      lua_setfield(L, -2, name);
      // The key's own string when Lua interns it (pushed twice, the same address), which the
      // table keeps alive; a longer name is looked up in the table.
      const char* once = lua_pushstring(L, name);
      const char* twice = lua_pushstring(L, name);
      self.names_[which].push_back(once == twice ? once : nullptr);
      lua_pop(L, 2);
    }
    return lua_gettop(L);
  };
  const Declared& d = *self.declared_;
  const int params = index_table(kParameters, d.params.size(), [&](size_t i) { return d.params[i].first.c_str(); });
  const int vars = index_table(kVariables, d.vars.size(), [&](size_t i) { return d.vars[i].c_str(); });
  lua_pushglobaltable(L);  // read raw, as declare read them
  lua_pushliteral(L, "step");
  lua_rawget(L, -2);
  self.step_ = luaL_ref(L, LUA_REGISTRYINDEX);
  lua_pushliteral(L, "init");
  lua_rawget(L, -2);
  self.init_ = luaL_ref(L, LUA_REGISTRYINDEX);
  lua_pop(L, 1);

  // The module: one table, pointed at each module in turn. Its only own fields are id and step,
  // rewritten before every call, so nothing a script writes there outlives the call; the
  // methods sit behind its metatable, and a new field is an error. get and set find variables
  // in their upvalue, param the parameters in its own.
  lua_createtable(L, 0, 2);
  for (const char* key : {"id", "step"}) {
    lua_pushstring(L, key);
    lua_pushinteger(L, 0);
    lua_rawset(L, -3);
  }
  lua_createtable(L, 0, 2);  // its metatable
  lua_createtable(L, 0, 8);  // the methods
  static constexpr luaL_Reg kByVariable[] = {{"get", &LuaState::get}, {"set", &LuaState::set}, {nullptr, nullptr}};
  lua_pushvalue(L, vars);
  luaL_setfuncs(L, kByVariable, 1);
  lua_pushvalue(L, params);
  lua_pushcclosure(L, &LuaState::param, 1);
  lua_setfield(L, -2, "param");
  // The tables m:inbox and m:neighbors hand out (their upvalues), and the metatable that lets
  // no entry be added to them.
  lua_createtable(L, 0, 2);
  lua_pushcfunction(L, &LuaState::new_entry);
  lua_setfield(L, -2, "__newindex");
  lua_pushboolean(L, 0);
  lua_setfield(L, -2, "__metatable");
  self.read_only_ = luaL_ref(L, LUA_REGISTRYINDEX);
  for (int pool = 0; pool < 3; ++pool) lua_newtable(L);  // kLists, kMessages, kWords
  lua_pushvalue(L, -3);
  lua_pushcclosure(L, &LuaState::neighbors, 1);
  lua_setfield(L, -5, "neighbors");
  lua_pushliteral(L, "from");
  lua_pushliteral(L, "data");
  lua_pushcclosure(L, &LuaState::inbox, 5);
  lua_setfield(L, -2, "inbox");
  static constexpr luaL_Reg kMethods[] = {
      {"send", &LuaState::send},         {"broadcast", &LuaState::broadcast}, {"random", &LuaState::random},
      {"position", &LuaState::position}, {"moving", &LuaState::moving},       {"move", &LuaState::move},
      {"pivot", &LuaState::pivot},       {"push", &LuaState::push},           {nullptr, nullptr}};
  luaL_setfuncs(L, kMethods, 0);
  lua_setfield(L, -2, "__index");
  lua_pushcfunction(L, &LuaState::new_field);
  lua_setfield(L, -2, "__newindex");
  lua_pushboolean(L, 0);
  lua_setfield(L, -2, "__metatable");
  lua_setmetatable(L, -2);
  self.module_ = luaL_ref(L, LUA_REGISTRYINDEX);
  lua_pop(L, 2);  // params, vars
  return 0;
}

bool LuaState::prepare(const Declared& d) {
  declared_ = &d;
  for (const auto& [name, value] : d.params) param_values_.push_back(value);
  lua_pushcfunction(L_, &LuaState::bind_host);
  if (!call(0, 0)) return failed();

  luaL_requiref(L_, LUA_DBLIBNAME, luaopen_debug, 0);  // for kFreeze only: never a global
  const int debug = lua_gettop(L_);
  if (luaL_loadbufferx(L_, kFreeze, std::strlen(kFreeze), LuaSandbox::kHostChunk, "t") != LUA_OK) return failed();
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
  // Outside a protected call: lua_checkstack says no where luaL_checkstack would reach Lua's panic.
  if (quadruples > 4'000'000 || !lua_checkstack(L_, int(quadruples) + 8)) {
    error_ = "the script holds too many functions and tables to check (" + std::to_string(quadruples / 4) +
             " upvalues and metamethods)";
    return false;
  }
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

void LuaState::run(sim::ModuleContext& m, bool initializing, bool after_init) {
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

// The call run counted in a fresh state, made from the script as this one was (its own watchdog
// lent, so that no thread is started): the message of its failure, empty when it went through.
std::string LuaState::run_counted(sim::ModuleContext& m, bool initializing, bool after_init) {
  LuaState fresh(display_, text_, sandbox_.limits(), &sandbox_.watchdog());
  if (fresh.error().empty()) fresh.prepare(*declared_);
  if (!fresh.error().empty()) return fresh.error();
  return *fresh.run_here(m, initializing, after_init, true);
}

// The call run in this state, counted or not: the message of its failure, empty when it went
// through, nothing when it was uncounted and interrupted.
std::optional<std::string> LuaState::run_here(sim::ModuleContext& m, bool initializing, bool after_init, bool counted) {
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
LuaSandbox::Outcome LuaState::attempt(int function, bool counted) {
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
bool LuaState::call(int args, int results) { return sandbox_.call(args, results, true) == LuaSandbox::Outcome::kOk; }
// A script's error may be megabytes long: what is shown of it is cut, as a watchpoint's line is.
std::string LuaState::pop_message() {
  constexpr size_t kShown = 1000;
  std::string message = "an error that is not a string";
  if (lua_type(L_, -1) == LUA_TSTRING) {
    size_t length = 0;
    const char* text = lua_tolstring(L_, -1, &length);
    message.assign(text, std::min(length, kShown));
    if (length > kShown) message += "... (" + std::to_string(length - kShown) + " bytes more)";
  }
  lua_pop(L_, 1);
  return message;
}
bool LuaState::failed() {
  error_ = pop_message();
  return false;
}

// The check (an upvalue, a frozen table's metamethod) whose value a call changed, or nullptr.
const LuaState::Check* LuaState::changed_check() {
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
int LuaState::read_declaration(lua_State* L) {
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

}  // namespace dw::scenarios
