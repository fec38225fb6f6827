// The sandbox's library functions that build their results in lauxlib's buffer (string.rep,
// format, gsub, table.concat, utf8.char ...): tried again after a full collection when the buffer
// is refused memory, without running the script's code twice (see `buffered`).
#include <cstring>

#include "scenarios/lua_host/lua_sandbox.h"

namespace dw::scenarios {

// buffered(f, prepare, ...): pcall(f, ...) for a library function that builds its result in
// lauxlib's buffer (string.rep, format, gsub, table.concat, ...). Lua asks again for what the
// allocator refused after a full collection, so the cap is met only by what the state holds; the
// buffer asks the allocator directly and fails at once, so whether it fails depends on how much
// garbage the collector has yet to take, which differs with the state's history (an uncounted try
// taken back leaves more). So a call refused memory is tried again after a full collection, and
// refused then, the memory is full: a memory stop. Trying again must not run the script's code
// twice: `prepare` (when not false) first makes the arguments plain under the pcall, running the
// metamethods and callbacks `f` would run, once; a replacement it made (see `replaying`) starts
// again from its first answer.
int LuaSandbox::buffered(lua_State* L) {
  LuaSandbox& s = of(L);
  if (lua_toboolean(L, 2)) {
    lua_pushvalue(L, 2);
    lua_rotate(L, 3, 1);  // f, prepare, prepare, ...
    if (lua_pcall(L, lua_gettop(L) - 3, LUA_MULTRET, 0) != LUA_OK) {
      lua_pushboolean(L, 0);
      lua_insert(L, -2);
      return 2;
    }
  }
  lua_remove(L, 2);
  const int n = lua_gettop(L);  // f and its arguments
  luaL_checkstack(L, n + 1, "too many arguments");
  for (int attempt = 1;; ++attempt) {
    for (int i = 1; i <= n; ++i) lua_pushvalue(L, i);
    if (lua_pcall(L, n - 1, LUA_MULTRET, 0) == LUA_OK) {
      lua_pushboolean(L, 1);
      lua_insert(L, n + 1);
      return lua_gettop(L) - n;
    }
    const bool refused = s.stop_ == Stop::kNone && lua_type(L, -1) == LUA_TSTRING &&
                         std::strcmp(lua_tostring(L, -1), "not enough memory") == 0;
    if (!refused) {  // any other error, as pcall gives it
      lua_pushboolean(L, 0);
      lua_insert(L, -2);
      return 2;
    }
    if (attempt == 2) stop(L, s.refused_why_, 0);
    lua_settop(L, n);
    lua_gc(L, LUA_GCCOLLECT);
    for (int i = 2; i <= n; ++i) {
      if (lua_tocfunction(L, i) != &LuaSandbox::replacement) continue;
      lua_pushinteger(L, 0);
      lua_setupvalue(L, i, 3);
    }
  }
}

// plain_concat(t, sep, i, j): table.concat's arguments, with a table that has a metatable read
// into a plain one first (its __len and __index run here, in concat's order, up to the first value
// concat refuses).
int LuaSandbox::plain_concat(lua_State* L) {
  lua_settop(L, 4);
  if (lua_type(L, 1) != LUA_TTABLE || !lua_getmetatable(L, 1)) return 4;
  lua_pop(L, 1);
  // What concat checks before it reads the table, left for concat to refuse.
  if (!lua_isnoneornil(L, 2) && !lua_isstring(L, 2)) return 4;
  int ok = 1;
  const lua_Integer first = lua_isnoneornil(L, 3) ? 1 : lua_tointegerx(L, 3, &ok);
  if (!ok) return 4;
  const lua_Integer last = lua_isnoneornil(L, 4) ? luaL_len(L, 1) : lua_tointegerx(L, 4, &ok);
  if (!ok) return 4;
  lua_newtable(L);
  for (lua_Integer k = first; k <= last; ++k) {
    const int type = lua_geti(L, 1, k);
    lua_rawseti(L, -2, k);
    if ((type != LUA_TSTRING && type != LUA_TNUMBER) || k == last) break;
  }
  lua_replace(L, 1);
  lua_pushinteger(L, first);
  lua_replace(L, 3);
  lua_pushinteger(L, last);
  lua_replace(L, 4);
  return 4;
}

// plain_format(fmt, ...): string.format's arguments, with a table or other object the format
// reads as a string (%s) turned into its string here as tostring shows it (its __tostring, else no
// address: lua_fixed_order.cpp), up to the first item format refuses. %p, an address, is refused.
int LuaSandbox::plain_format(lua_State* L) {
  const int top = lua_gettop(L);
  size_t length = 0;
  const char* format = lua_type(L, 1) == LUA_TSTRING ? lua_tolstring(L, 1, &length) : nullptr;
  int arg = 1;
  for (size_t i = 0; i < length; ++i) {
    if (format[i] != '%') continue;
    if (++i < length && format[i] == '%') continue;
    while (i < length && format[i] != '\0' && std::strchr("-+ #0123456789.", format[i])) ++i;
    if (i >= length || ++arg > top || format[i] == '\0' || !std::strchr("cdiuoxXaAfFeEgGpqs", format[i])) break;
    if (format[i] == 'p') return luaL_error(L, "string.format: %%p shows an address, which differs from run to run");
    const int type = lua_type(L, arg);
    if (format[i] == 's' && type != LUA_TSTRING && type != LUA_TNUMBER) {
      push_plain_string(L, arg);
      lua_replace(L, arg);
    }
  }
  return top;
}

// replaying(s, p, r, n): string.gsub's arguments, with a function or table replacement `r` made a
// `replacement` that remembers its answers.
int LuaSandbox::replaying(lua_State* L) {
  lua_settop(L, 4);
  if (lua_type(L, 3) != LUA_TFUNCTION && lua_type(L, 3) != LUA_TTABLE) return 4;
  lua_pushvalue(L, 3);
  lua_newtable(L);
  lua_pushinteger(L, 0);
  lua_pushcclosure(L, &LuaSandbox::replacement, 3);
  lua_replace(L, 3);
  return 4;
}

// What gsub calls for each match: the first time, the script's replacement (the function called
// with the captures, or the table indexed by the first), its answer or error kept; after a try
// again, the kept one. Upvalues: the script's replacement, the answers (ok at 2k - 1, the value or
// error at 2k), the matches asked in this try.
int LuaSandbox::replacement(lua_State* L) {
  const lua_Integer k = lua_tointeger(L, lua_upvalueindex(3)) + 1;
  lua_pushinteger(L, k);
  lua_replace(L, lua_upvalueindex(3));
  if (lua_rawgeti(L, lua_upvalueindex(2), 2 * k - 1) != LUA_TNIL) {
    const bool ok = lua_toboolean(L, -1);
    lua_rawgeti(L, lua_upvalueindex(2), 2 * k);
    return ok ? 1 : lua_error(L);
  }
  lua_pop(L, 1);
  if (lua_type(L, lua_upvalueindex(1)) == LUA_TFUNCTION) {
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
  } else {  // r[first capture], its __index called from C as gsub would
    lua_settop(L, 1);
    lua_pushcfunction(L, [](lua_State* L) {
      lua_gettable(L, 1);
      return 1;
    });
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_rotate(L, 1, 2);
  }
  const int status = lua_pcall(L, lua_gettop(L) - 1, 1, 0);
  lua_pushboolean(L, status == LUA_OK);
  lua_rawseti(L, lua_upvalueindex(2), 2 * k - 1);
  lua_pushvalue(L, -1);
  lua_rawseti(L, lua_upvalueindex(2), 2 * k);
  return status == LUA_OK ? 1 : lua_error(L);
}

}  // namespace dw::scenarios
