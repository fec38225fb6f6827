#include "scenarios/lua_program.h"

#include <lua.hpp>

#include <array>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <thread>
#include <unordered_map>

namespace dw::scenarios {
namespace {

// Run once in every Lua state after the script: freezes the globals and every table reached from
// them or from a function's upvalues (emptied, their contents behind a read-only metatable), and
// lists the upvalues to check after each call, as {function, index, name, value} quadruples.
// Locals of the script (`local n = 0` outside step) are upvalues: writing one keeps state outside
// the module's variables, which a rollback could not restore.
constexpr const char* kFreeze = R"lua(
local G, debug = ...
local next, type, tostring, error, setmetatable, getmetatable = next, type, tostring, error, setmetatable, getmetatable
local frozen, seen, checks = {}, {}, {}
local function deny(_, k)
  error("writes '" .. tostring(k) .. "' outside the module's variables (a script keeps its state with m:set)", 2)
end
local freeze_value
local function freeze(t)
  if frozen[t] or getmetatable(t) ~= nil then return end
  frozen[t] = true
  local hidden = {}
  for k, v in next, t do hidden[k] = v end
  for k in next, hidden do t[k] = nil end
  setmetatable(t, { __index = hidden, __newindex = deny, __len = function() return #hidden end,
                    __pairs = function() return next, hidden, nil end, __metatable = false })
  for _, v in next, hidden do freeze_value(v) end
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
        checks[#checks + 1] = v
        checks[#checks + 1] = i
        checks[#checks + 1] = name
        checks[#checks + 1] = value
      end
      i = i + 1
    end
  end
end
freeze(G)
return checks
)lua";

// What the script declares of itself (read from its `program` table when it is loaded).
struct Declared {
  std::vector<std::string> vars;
  std::vector<std::pair<std::string, int64_t>> params;  // with their values for this scenario
  bool has_init = false;
};

// One Lua state: the script loaded into it, sandboxed and frozen. Owned by one thread at a time.
class LuaState {
 public:
  LuaState(const std::string& display, const std::string& text, const LuaLimits& limits)
      : limits_(limits), display_(display) {
    L_ = lua_newstate(&LuaState::allocate, this);
    if (!L_) {
      error_ = display + ": no memory for a Lua state";
      return;
    }
    *static_cast<LuaState**>(lua_getextraspace(L_)) = this;
    lua_sethook(L_, &LuaState::count_hook, LUA_MASKCOUNT, kHookEvery);
    open_sandbox();
    if (luaL_loadbufferx(L_, text.data(), text.size(), ("@" + display).c_str(), "t") != LUA_OK || !call(0, 0)) {
      error_ = pop_message();
      return;
    }
  }
  ~LuaState() {
    if (L_) lua_close(L_);
  }
  LuaState(const LuaState&) = delete;
  LuaState& operator=(const LuaState&) = delete;

  lua_State* L() const { return L_; }
  const std::string& error() const { return error_; }

  // Reads `program`, `step` and `init` as the script defined them; false with error() set when
  // they are not as DESIGN §11 says.
  bool declare(Declared& d) {
    auto fail = [&](const std::string& why) {
      error_ = display_ + ": " + why;
      lua_settop(L_, 0);
      return false;
    };
    if (lua_getglobal(L_, "program") != LUA_TTABLE) return fail("the script must set `program = { vars = {...} }`");
    if (lua_getfield(L_, -1, "vars") != LUA_TTABLE) return fail("`program.vars` must be a list of variable names");
    for (lua_Integer i = 1; lua_rawgeti(L_, -1, i) != LUA_TNIL; ++i) {
      if (lua_type(L_, -1) != LUA_TSTRING) return fail("`program.vars` must list names (strings)");
      d.vars.emplace_back(lua_tostring(L_, -1));
      lua_pop(L_, 1);
    }
    lua_pop(L_, 2);
    if (lua_getfield(L_, -1, "params") != LUA_TNIL) {
      if (!lua_istable(L_, -1)) return fail("`program.params` must be a table of names and default integers");
      for (lua_pushnil(L_); lua_next(L_, -2); lua_pop(L_, 1)) {
        int ok = 0;
        const lua_Integer v = lua_tointegerx(L_, -1, &ok);
        if (lua_type(L_, -2) != LUA_TSTRING || !ok || lua_type(L_, -1) != LUA_TNUMBER)
          return fail("`program.params` must map names to integers");
        d.params.emplace_back(lua_tostring(L_, -2), v);
      }
    }
    lua_pop(L_, 2);
    if (lua_getglobal(L_, "step") != LUA_TFUNCTION) return fail("the script must define `function step(m)`");
    const int init = lua_getglobal(L_, "init");
    if (init != LUA_TNIL && init != LUA_TFUNCTION) return fail("`init` must be a function (init(m)) or absent");
    d.has_init = init == LUA_TFUNCTION;
    lua_pop(L_, 2);
    return true;
  }

  // Binds the module API and freezes the script (see kFreeze); false with error() set.
  bool prepare(const Declared& d) {
    lua_newtable(L_);  // variable name -> index
    for (size_t i = 0; i < d.vars.size(); ++i) {
      lua_pushinteger(L_, lua_Integer(i));
      lua_setfield(L_, -2, d.vars[i].c_str());
    }
    vars_ = luaL_ref(L_, LUA_REGISTRYINDEX);
    lua_newtable(L_);  // parameter name -> value
    for (const auto& [name, value] : d.params) {
      lua_pushinteger(L_, value);
      lua_setfield(L_, -2, name.c_str());
    }
    params_ = luaL_ref(L_, LUA_REGISTRYINDEX);
    lua_getglobal(L_, "step");
    step_ = luaL_ref(L_, LUA_REGISTRYINDEX);
    lua_getglobal(L_, "init");
    init_ = luaL_ref(L_, LUA_REGISTRYINDEX);

    // The module: one userdata, pointed at each module in turn.
    *static_cast<LuaState**>(lua_newuserdatauv(L_, sizeof(LuaState*), 0)) = this;
    static constexpr luaL_Reg kMethods[] = {
        {"get", &LuaState::get},       {"set", &LuaState::set},     {"neighbors", &LuaState::neighbors},
        {"inbox", &LuaState::inbox},   {"send", &LuaState::send},   {"broadcast", &LuaState::broadcast},
        {"random", &LuaState::random}, {"param", &LuaState::param}, {nullptr, nullptr}};
    lua_newtable(L_);  // the userdata's metatable
    lua_newtable(L_);  // its methods
    luaL_setfuncs(L_, kMethods, 0);
    lua_pushcclosure(L_, &LuaState::index, 1);
    lua_setfield(L_, -2, "__index");
    lua_pushboolean(L_, 0);
    lua_setfield(L_, -2, "__metatable");
    lua_setmetatable(L_, -2);
    module_ = luaL_ref(L_, LUA_REGISTRYINDEX);

    luaL_requiref(L_, LUA_DBLIBNAME, luaopen_debug, 0);  // for kFreeze only: never a global
    const int debug = lua_gettop(L_);
    if (luaL_loadbufferx(L_, kFreeze, std::strlen(kFreeze), "=dwatch", "t") != LUA_OK) return failed();
    lua_pushglobaltable(L_);
    lua_pushvalue(L_, debug);
    if (!call(2, 1)) return failed();
    checks_ = luaL_ref(L_, LUA_REGISTRYINDEX);
    lua_pop(L_, 1);
    lua_rawgeti(L_, LUA_REGISTRYINDEX, checks_);
    check_count_ = lua_Integer(lua_rawlen(L_, -1));
    lua_pop(L_, 1);
    return true;
  }

  // Runs init (when `initializing`) or step for one module. When the script fails, the module's
  // error says where: the script's file:line, the module and the step.
  void run(sim::ModuleContext& m, bool initializing, bool after_init = false) {
    module_context_ = &m;
    after_init_ = after_init;
    draws_ = 0;
    lua_rawgeti(L_, LUA_REGISTRYINDEX, initializing ? init_ : step_);
    lua_rawgeti(L_, LUA_REGISTRYINDEX, module_);
    std::string message;
    if (!call(1, 0)) {
      message = pop_message();
    } else if (const char* name = changed_upvalue()) {
      message = display_ + ": " + (initializing ? "init" : "step") + " wrote the local '" + name +
                "' declared outside it: a script keeps its state in its variables (m:set), which a rollback restores";
    }
    if (!message.empty()) m.fail("at step " + std::to_string(m.step()) + ": " + message);
    module_context_ = nullptr;
  }

 private:
  static constexpr int kHookEvery = 1000;

  static LuaState& of(lua_State* L) { return **static_cast<LuaState**>(lua_getextraspace(L)); }
  static sim::ModuleContext& module(lua_State* L) {
    LuaState& s = of(L);
    if (!s.module_context_) luaL_error(L, "the module is only there while init or step runs");
    return *s.module_context_;
  }

  static void* allocate(void* self_ptr, void* ptr, size_t old_size, size_t new_size) {
    auto& self = *static_cast<LuaState*>(self_ptr);
    const size_t old = ptr ? old_size : 0;
    if (new_size == 0) {
      std::free(ptr);
      self.bytes_ -= old;
      return nullptr;
    }
    if (new_size > old && self.bytes_ + (new_size - old) > self.limits_.memory_bytes) return nullptr;
    void* p = std::realloc(ptr, new_size);
    if (p) self.bytes_ = self.bytes_ - old + new_size;
    return p;
  }

  static void count_hook(lua_State* L, lua_Debug*) {
    LuaState& s = of(L);
    s.executed_ += kHookEvery;
    if (s.executed_ <= s.limits_.instructions) return;
    // The hook runs inside the function it interrupted: level 0 is the script's line. (Nothing
    // with a destructor may be alive here: lua_error jumps over C++ frames.)
    lua_Debug at;
    if (lua_getstack(L, 0, &at) && lua_getinfo(L, "Sl", &at) && at.currentline > 0)
      lua_pushfstring(L, "%s:%d: ", at.short_src, at.currentline);
    else lua_pushliteral(L, "");
    lua_pushfstring(L, "ran more than %I instructions in one call (an endless loop?)",
                    lua_Integer(s.limits_.instructions));
    lua_concat(L, 2);
    lua_error(L);
  }

  void open_sandbox() {
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
    for (const char* name : {"dofile", "loadfile", "load", "print", "collectgarbage", "rawset", "require"}) {
      lua_pushnil(L_);
      lua_setglobal(L_, name);
    }
    lua_getglobal(L_, LUA_MATHLIBNAME);  // m:random is the module's generator; math's is not
    for (const char* name : {"random", "randomseed"}) {
      lua_pushnil(L_);
      lua_setfield(L_, -2, name);
    }
    lua_pop(L_, 1);
  }

  // pcall with the instruction budget reset; the error message stays on the stack when false.
  bool call(int args, int results) {
    executed_ = 0;
    return lua_pcall(L_, args, results, 0) == LUA_OK;
  }
  std::string pop_message() {
    std::string message = lua_type(L_, -1) == LUA_TSTRING ? lua_tostring(L_, -1) : "an error that is not a string";
    lua_pop(L_, 1);
    return message;
  }
  bool failed() {
    error_ = pop_message();
    return false;
  }

  // The name of an upvalue a call changed, or nullptr.
  const char* changed_upvalue() {
    if (check_count_ == 0) return nullptr;
    lua_rawgeti(L_, LUA_REGISTRYINDEX, checks_);
    const char* changed = nullptr;
    for (lua_Integer i = 1; i + 3 <= check_count_ && !changed; i += 4) {
      lua_rawgeti(L_, -1, i);  // the function
      lua_rawgeti(L_, -2, i + 1);
      const int index = int(lua_tointeger(L_, -1));
      lua_pop(L_, 1);
      lua_getupvalue(L_, -1, index);
      lua_rawgeti(L_, -3, i + 3);
      if (!lua_rawequal(L_, -1, -2)) {
        lua_rawgeti(L_, -4, i + 2);
        changed = lua_tostring(L_, -1);  // kept alive by the checks table
        lua_pop(L_, 1);
      }
      lua_pop(L_, 3);
    }
    lua_pop(L_, 1);
    return changed;
  }

  // m.id, m.step, and the methods.
  static int index(lua_State* L) {
    const char* key = luaL_checkstring(L, 2);
    if (std::strcmp(key, "id") == 0) {
      lua_pushinteger(L, module(L).id());
    } else if (std::strcmp(key, "step") == 0) {
      lua_pushinteger(L, module(L).step());
    } else {
      lua_getfield(L, lua_upvalueindex(1), key);
    }
    return 1;
  }

  static uint32_t variable(lua_State* L, int arg) {
    const char* name = luaL_checkstring(L, arg);
    lua_rawgeti(L, LUA_REGISTRYINDEX, of(L).vars_);
    if (lua_getfield(L, -1, name) != LUA_TNUMBER)
      luaL_error(L, "'%s' is not a variable of this program (declare it in program.vars)", name);
    const auto index = static_cast<uint32_t>(lua_tointeger(L, -1));
    lua_pop(L, 2);
    return index;
  }

  static int64_t integer(lua_State* L, int arg, const char* what) {
    int ok = 0;
    const lua_Integer v = lua_tointegerx(L, arg, &ok);
    if (!ok || lua_type(L, arg) != LUA_TNUMBER)
      luaL_error(L, "%s must be an integer, not %s", what,
                 lua_type(L, arg) == LUA_TNUMBER ? lua_tostring(L, arg) : luaL_typename(L, arg));
    return v;
  }

  static int get(lua_State* L) {
    const uint32_t v = variable(L, 2);
    // At step 0, after init, what init set stands for the values before the step.
    lua_pushinteger(L, of(L).after_init_ ? module(L).assigned(v) : module(L).get(v));
    return 1;
  }
  static int set(lua_State* L) {
    const uint32_t v = variable(L, 2);
    module(L).set(v, integer(L, 3, "a variable's value"));
    return 0;
  }
  static int neighbors(lua_State* L) {
    const auto n = module(L).neighbors();
    lua_createtable(L, int(n.size()), 0);
    for (size_t i = 0; i < n.size(); ++i) {
      lua_pushinteger(L, n[i]);
      lua_rawseti(L, -2, lua_Integer(i + 1));
    }
    return 1;
  }
  static int inbox(lua_State* L) {
    const auto in = module(L).inbox();
    lua_createtable(L, int(in.size()), 0);
    for (size_t i = 0; i < in.size(); ++i) {
      lua_createtable(L, 0, 2);
      lua_pushinteger(L, in[i].from);
      lua_setfield(L, -2, "from");
      const auto words = in[i].payload();
      lua_createtable(L, int(words.size()), 0);
      for (size_t w = 0; w < words.size(); ++w) {
        lua_pushinteger(L, words[w]);
        lua_rawseti(L, -2, lua_Integer(w + 1));
      }
      lua_setfield(L, -2, "data");
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
    const lua_Integer n = luaL_len(L, arg);
    if (n > lua_Integer(sim::Message::kMaxWords))
      luaL_error(L, "a message holds at most %d integers, not %I", int(sim::Message::kMaxWords), n);
    Payload p{{}, static_cast<size_t>(n)};
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_geti(L, arg, i);
      p.words[size_t(i - 1)] = integer(L, -1, "a message word");
      lua_pop(L, 1);
    }
    return p;
  }
  static int send(lua_State* L) {
    sim::ModuleContext& m = module(L);
    const int64_t to = integer(L, 2, "the module sent to");
    if (to < 0 || to > int64_t(UINT32_MAX) || !m.is_neighbor(sim::ModuleId(to)))
      luaL_error(L, "module %d sent to %I, which is not its neighbour", int(m.id()), lua_Integer(to));
    const Payload words = payload(L, 3);
    m.send(sim::ModuleId(to), words.span());
    return 0;
  }
  static int broadcast(lua_State* L) {
    const Payload words = payload(L, 2);
    module(L).broadcast(words.span());
    return 0;
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
  static int param(lua_State* L) {
    const char* name = luaL_checkstring(L, 2);
    lua_rawgeti(L, LUA_REGISTRYINDEX, of(L).params_);
    if (lua_getfield(L, -1, name) != LUA_TNUMBER)
      luaL_error(L, "'%s' is not a parameter of this program (declare it in program.params)", name);
    return 1;
  }

  lua_State* L_ = nullptr;
  LuaLimits limits_;
  std::string display_, error_;
  size_t bytes_ = 0;
  int64_t executed_ = 0;
  int vars_ = LUA_NOREF, params_ = LUA_NOREF, step_ = LUA_NOREF, init_ = LUA_NOREF, module_ = LUA_NOREF,
      checks_ = LUA_NOREF;
  lua_Integer check_count_ = 0;
  sim::ModuleContext* module_context_ = nullptr;
  bool after_init_ = false;  // step 0 of a script with init: m:get reads what init set
  uint32_t draws_ = 0;
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
    LuaState& s = state();
    if (!s.error().empty()) {
      m.fail("at step " + std::to_string(m.step()) + ": " + s.error());
      return;
    }
    if (m.step() == 0 && declared_.has_init) s.run(m, true);
    s.run(m, false, m.step() == 0 && declared_.has_init);
  }

 private:
  // This thread's Lua state, made on its first step: a state is used by one thread only.
  LuaState& state() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    std::unique_ptr<LuaState>& s = states_[std::this_thread::get_id()];
    if (!s) {
      s = std::make_unique<LuaState>(display_, text_, limits_);
      if (s->error().empty()) s->prepare(declared_);  // declared once, when the scenario loaded
    }
    return *s;
  }

  std::string display_, text_;
  Declared declared_;
  LuaLimits limits_;
  mutable std::mutex mutex_;
  mutable std::unordered_map<std::thread::id, std::unique_ptr<LuaState>> states_;
};

}  // namespace

std::unique_ptr<const sim::HostProgram> make_lua_program(const std::string& display, const std::string& text,
                                                         TableReader& params, std::string& why,
                                                         const LuaLimits& limits) {
  LuaState probe(display, text, limits);
  Declared declared;
  if (!probe.error().empty() || !probe.declare(declared) || !probe.prepare(declared)) {
    why = probe.error();
    return nullptr;
  }
  bool ok = true;
  for (auto& [name, value] : declared.params)
    if (params.has(name)) {
      const auto v = params.integer(name, INT64_MIN, INT64_MAX);
      if (v) value = *v;
      else ok = false;
    }
  if (!ok) return nullptr;
  return std::make_unique<LuaProgram>(display, text, std::move(declared), limits);
}

}  // namespace dw::scenarios
