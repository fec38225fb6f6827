// The module API a script calls on `m` (docs/design.md §11; lua_state.h): its variables and
// parameters, its neighbours and inbox (tables from pools kept from call to call), sending, random
// draws and, in a world with bodies, the body's sensing and actuation. The C functions that
// LuaState::prepare binds into the module table, and their helpers.
#include "scenarios/lua_host/lua_state.h"

#include "sim/message.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <span>

namespace dw::scenarios {

int LuaState::new_field(lua_State* L) {
  return luaL_error(L, "sets m.%s: the module has no such field (a script keeps its state with m:set)",
                    luaL_tolstring(L, 2, nullptr));
}

// The index of the variable (kVariables) or parameter (kParameters) named by argument 2. Names
// of up to 40 bytes are interned by Lua: the string passed is the very one the table of names
// holds (which keeps it alive), so comparing addresses finds it; the upvalue table looks up the
// rest, and reports a name that is neither. Past kScannedNames names the table alone, a hash
// lookup: the scan is no instruction the budget counts, and 100,000 variables made each call 1.67 s.
uint32_t LuaState::lookup(lua_State* L, Names which) {
  constexpr size_t kScannedNames = 16;
  const std::vector<const char*>& names = of(L).names_[which];
  if (names.size() <= kScannedNames)
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

int64_t LuaState::integer(lua_State* L, int arg, const char* what) {
  if (lua_isinteger(L, arg)) return lua_tointeger(L, arg);
  int ok = 0;  // a float with an integral value, or not a number at all
  const lua_Integer v = lua_tointegerx(L, arg, &ok);
  if (!ok || lua_type(L, arg) != LUA_TNUMBER) {
    // Lua writes 0/0 as "-nan" (its sign bit set): a NaN is "nan" whatever its sign.
    const bool nan = lua_type(L, arg) == LUA_TNUMBER && std::isnan(lua_tonumber(L, arg));
    luaL_error(L, "%s must be an integer, not %s", what,
               nan                               ? "nan"
               : lua_type(L, arg) == LUA_TNUMBER ? lua_tostring(L, arg)
                                                 : luaL_typename(L, arg));
  }
  return v;
}

int LuaState::get(lua_State* L) {
  const uint32_t v = lookup(L, kVariables);
  // At step 0, after init, what init set stands for the values before the step.
  lua_pushinteger(L, of(L).after_init_ ? module(L).assigned(v) : module(L).get(v));
  return 1;
}
int LuaState::set(lua_State* L) {
  const uint32_t v = lookup(L, kVariables);
  module(L).set(v, integer(L, 3, "a variable's value"));
  return 0;
}
int LuaState::new_entry(lua_State* L) {
  return luaL_error(L, "adds '%s' to a table of m:inbox() or m:neighbors(), which are the step's own (copy it first)",
                    luaL_tolstring(L, 2, nullptr));
}

// A table of the pool at `upvalue` for this call at the top of the stack, holding `size`
// entries: those from 1 to `size` are the caller's to fill, the ones after are cleared here.
void LuaState::take_table(lua_State* L, PoolKind kind, int upvalue, uint32_t size) {
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

int LuaState::neighbors(lua_State* L) {
  const auto n = module(L).neighbors();
  of(L).take_table(L, kLists, 1, uint32_t(n.size()));
  for (size_t i = 0; i < n.size(); ++i) {
    lua_pushinteger(L, n[i]);
    lua_rawseti(L, -2, lua_Integer(i + 1));
  }
  return 1;
}
// { { from = id, data = { words } }, ... }. Upvalues: the three pools, "from" and "data".
int LuaState::inbox(lua_State* L) {
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
struct LuaState::Payload {
  std::array<int64_t, sim::Message::kMaxWords> words;
  size_t size;
  std::span<const int64_t> span() const { return {words.data(), size}; }
};
LuaState::Payload LuaState::payload(lua_State* L, int arg) {
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
int LuaState::send(lua_State* L) {
  sim::ModuleContext& m = module(L);
  const int64_t to = integer(L, 2, "the module sent to");
  if (to < 0 || to > int64_t(UINT32_MAX) || !m.is_neighbor(sim::ModuleId(to)))
    luaL_error(L, "module %d sent to %I, which is not its neighbour", int(m.id()), lua_Integer(to));
  const Payload words = payload(L, 3);
  count_messages(L, "send", 1);
  m.send(sim::ModuleId(to), words.span());
  return 0;
}
int LuaState::broadcast(lua_State* L) {
  const Payload words = payload(L, 2);
  sim::ModuleContext& m = module(L);
  count_messages(L, "broadcast", m.neighbors().size());
  m.broadcast(words.span());
  return 0;
}
// Counts `n` more messages of this call against the limit, or raises the error.
void LuaState::count_messages(lua_State* L, const char* method, size_t n) {
  LuaState& s = of(L);
  const uint32_t limit = s.sandbox_.limits().messages;
  if (n > limit - std::min(s.messages_, limit))
    luaL_error(L, "m:%s: this call would send more than %d messages, the limit of one call of init or step", method,
               int(limit));
  s.messages_ += uint32_t(n);
}
// m:random(n): 0 .. n - 1; m:random(0): 64 random bits (as Lua's math.random(0)). Each draw of
// a step reads its own stream, the first stream 0.
int LuaState::random(lua_State* L) {
  const int64_t n = integer(L, 2, "the bound of m:random(n)");
  if (n < 0) luaL_error(L, "m:random(n) needs n >= 1 (or 0 for 64 bits), not %I", lua_Integer(n));
  sim::ModuleContext& m = module(L);
  const uint32_t stream = of(L).draws_++;
  lua_pushinteger(L, n == 0 ? static_cast<lua_Integer>(m.random(stream)) : m.uniform(n, stream));
  return 1;
}
// The body (docs/design.md §11, mirroring sim::ModuleContext's sensing and actuation): only in a world
// with bodies, which the scenario's [physics] makes.
sim::ModuleContext& LuaState::body(lua_State* L, const char* method) {
  sim::ModuleContext& m = module(L);
  if (!m.has_body())
    luaL_error(L, "m:%s() needs a body, and this world has none (the scenario's [physics] is off)", method);
  return m;
}
// Arguments 2, 3 and 4 of m:METHOD as a vector. A NaN or an infinity (or a number past a float's
// range) would reach the world's poses and silently corrupt them: a program error naming the call,
// as a pivot into no cell is.
sim::Vec3 LuaState::vector(lua_State* L, const char* method) {
  sim::Vec3 v;
  for (int i = 0; i < 3; ++i) {
    const lua_Number given = luaL_checknumber(L, 2 + i);
    if (std::isfinite(given) && std::abs(given) <= std::numeric_limits<float>::max()) {
      v[size_t(i)] = float(given);
      continue;
    }
    char shown[32];
    if (std::isnan(given)) std::snprintf(shown, sizeof shown, "nan");
    else std::snprintf(shown, sizeof shown, "%g", double(given));
    luaL_error(L, "m:%s: its %s is %s, not a finite number", method, i == 0 ? "x" : i == 1 ? "y" : "z", shown);
  }
  return v;
}
// m:position(): x, y, z of the body's centre as the step began, in module sizes.
int LuaState::position(lua_State* L) {
  const sim::Vec3& p = body(L, "position").pose().position;
  for (float c : p) lua_pushnumber(L, c);
  return 3;
}
// m:moving(): whether a lattice move of the module is under way.
int LuaState::moving(lua_State* L) {
  lua_pushboolean(L, body(L, "moving").moving());
  return 1;
}
// m:move(dx, dy, dz): a lattice move by one module size into a free cell, carried out as the
// world steps on (refused when the cell is taken or the module is already moving).
int LuaState::move(lua_State* L) {
  sim::ModuleContext& m = body(L, "move");
  m.move(vector(L, "move"));
  return 0;
}
// m:pivot(about, dx, dy, dz): a pivot about the neighbour `about` into the cell at (dx, dy, dz)
// from this one (a cube about the edge they share, a sphere rolling over it); a taken cell or a
// blocked sweep is a program error.
int LuaState::pivot(lua_State* L) {
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
int LuaState::push(lua_State* L) {
  sim::ModuleContext& m = body(L, "push");
  m.push(vector(L, "push"));
  return 0;
}

int LuaState::param(lua_State* L) {
  lua_pushinteger(L, of(L).param_values_[lookup(L, kParameters)]);
  return 1;
}

}  // namespace dw::scenarios
