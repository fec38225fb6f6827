// What a script could learn that differs from run to run, made the same on every run (see
// lua_sandbox.h): the order in which pairs and next visit a table's keys, and the addresses that
// tostring and string.format("%s") show for tables and functions.
//
// Lua places string keys by a hash whose seed each new state takes from the clock and from
// addresses (luai_makeseed, not settable through the API), and tables, functions and other
// objects by their addresses; so Lua's own next visits the keys of one table in an order that
// differs from state to state. A script that reads the first key pairs gives (or stops a loop
// early, or sets variables in the loop's order) would then compute different values on every run
// and on every thread. Here pairs and next visit keys in a fixed order instead: numbers
// ascending, then strings in byte order, then false and true. A key of any other type (a table,
// a function) has no place in that order: iterating over a table that holds one is an error.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "scenarios/lua_host/lua_sandbox.h"

namespace dw::scenarios {
namespace {

// A key in the fixed order, read from the stack (trivially destructible: it lives in Lua's memory).
struct OrderedKey {
  int rank = 0;  // 0 number, 1 string, 2 boolean
  bool integer = false;
  lua_Integer i = 0;
  lua_Number f = 0;
  const char* s = nullptr;  // kept alive by the table that holds the key
  size_t length = 0;
  lua_Integer slot = 0;  // where the key is in the table of keys (ordered_pairs)
};

// The key at `index`, or false when it has no place in the order.
bool read_key(lua_State* L, int index, OrderedKey& key) {
  switch (lua_type(L, index)) {
    case LUA_TNUMBER:
      key.rank = 0;
      key.integer = lua_isinteger(L, index);
      if (key.integer) key.i = lua_tointeger(L, index);
      else key.f = lua_tonumber(L, index);
      return true;
    case LUA_TSTRING:
      key.rank = 1;
      key.s = lua_tolstring(L, index, &key.length);
      return true;
    case LUA_TBOOLEAN:
      key.rank = 2;
      key.i = lua_toboolean(L, index);
      return true;
    default: return false;
  }
}

// Whether a comes before b. Integers and floats compare by value (a long double holds every
// 64-bit integer exactly; NaN is never a key).
bool before(const OrderedKey& a, const OrderedKey& b) {
  if (a.rank != b.rank) return a.rank < b.rank;
  if (a.rank == 0) {
    if (a.integer && b.integer) return a.i < b.i;
    const long double x = a.integer ? static_cast<long double>(a.i) : a.f;
    const long double y = b.integer ? static_cast<long double>(b.i) : b.f;
    return x < y;
  }
  if (a.rank == 1) {
    const int c = std::memcmp(a.s, b.s, std::min(a.length, b.length));
    return c != 0 ? c < 0 : a.length < b.length;
  }
  return a.i < b.i;
}

// Raises the error for a key (at `index`) of a type the order has no place for. Nothing with a
// destructor is alive here.
[[noreturn]] void unordered_key(lua_State* L, const char* function, int index) {
  luaL_error(L,
             "%s: the table has a key that is a %s, whose place among the keys would differ from run to run; "
             "dwatch visits keys in a fixed order (numbers, then strings, then booleans): key such a table "
             "by numbers or strings",
             function, luaL_typename(L, index));
  std::abort();  // luaL_error does not return
}

// The iterator ordered_pairs returns. Upvalues: the keys in order, and how many were visited.
int ordered_step(lua_State* L) {
  lua_Integer at = lua_tointeger(L, lua_upvalueindex(2));
  for (;;) {
    if (lua_rawgeti(L, lua_upvalueindex(1), ++at) == LUA_TNIL) return 1;
    lua_pushvalue(L, -1);
    // A key set to nil during the loop is passed over, as Lua's next passes it over.
    if (lua_rawget(L, 1) != LUA_TNIL) break;
    lua_pop(L, 2);
  }
  lua_pushinteger(L, at);
  lua_replace(L, lua_upvalueindex(2));
  return 2;
}

}  // namespace

// pairs(t): the __pairs metamethod's three values, as Lua's pairs; else an iterator over t's keys
// as they are when pairs is called, in the fixed order. (Lua leaves undefined what next does
// with a key added during a loop; here such a key is not visited.)
int LuaSandbox::ordered_pairs(lua_State* L) {
  luaL_checkany(L, 1);
  if (luaL_getmetafield(L, 1, "__pairs") != LUA_TNIL) {
    lua_pushvalue(L, 1);
    lua_call(L, 1, 3);
    return 3;
  }
  luaL_checktype(L, 1, LUA_TTABLE);
  lua_settop(L, 1);
  lua_newtable(L);  // 2: the keys, as next finds them
  lua_Integer n = 0;
  for (lua_pushnil(L); lua_next(L, 1);) {
    lua_pop(L, 1);
    lua_pushvalue(L, -1);
    lua_rawseti(L, 2, ++n);
  }
  charge(L, n > 1 ? double(n) * std::log2(double(n)) : double(n));
  // The keys read into records in Lua's memory (nothing here outlives an error), sorted.
  auto* keys = static_cast<OrderedKey*>(lua_newuserdatauv(L, sizeof(OrderedKey) * size_t(n), 0));  // 3
  for (lua_Integer k = 1; k <= n; ++k) {
    lua_rawgeti(L, 2, k);
    OrderedKey& key = keys[k - 1];
    key = OrderedKey{};
    if (!read_key(L, -1, key)) unordered_key(L, "pairs", -1);
    key.slot = k;
    lua_pop(L, 1);
  }
  std::stable_sort(keys, keys + n, before);
  lua_createtable(L, int(std::min<lua_Integer>(n, 1 << 24)), 0);  // 4: the keys in order
  for (lua_Integer k = 1; k <= n; ++k) {
    lua_rawgeti(L, 2, keys[k - 1].slot);
    lua_rawseti(L, 4, k);
  }
  lua_pushinteger(L, 0);
  lua_pushcclosure(L, &ordered_step, 2);
  lua_pushvalue(L, 1);
  lua_pushnil(L);
  return 3;
}

// next(t [, k]): the key after k in the fixed order (the first when k is nil) and its value, or
// nil after the last. A pass over t's keys: a loop of next over n keys takes n^2 steps, which
// are charged; pairs takes n log n.
int LuaSandbox::ordered_next(lua_State* L) {
  luaL_checktype(L, 1, LUA_TTABLE);
  lua_settop(L, 2);
  lua_pushnil(L);  // 3: the next key found so far
  OrderedKey after{}, best{}, key{};
  const bool first = lua_isnil(L, 2);
  if (!first && !read_key(L, 2, after)) unordered_key(L, "next", 2);
  bool found = false;
  lua_Integer n = 0;
  for (lua_pushnil(L); lua_next(L, 1);) {  // 4: a key, 5: its value
    ++n;
    if (!read_key(L, 4, key)) unordered_key(L, "next", 4);
    if ((first || before(after, key)) && (!found || before(key, best))) {
      lua_pushvalue(L, 4);
      lua_replace(L, 3);  // keeps the key's string alive for `best`
      best = key;
      found = true;
    }
    lua_pop(L, 1);
  }
  charge(L, double(n));
  if (!found) {
    lua_pushnil(L);
    return 1;
  }
  lua_pushvalue(L, 3);
  lua_pushvalue(L, 3);
  lua_rawget(L, 1);
  return 2;
}

// tostring(v): as Lua's, but a table, function or other object without __tostring is shown by
// its __name or its type alone: Lua shows its address, which differs from run to run.
int LuaSandbox::plain_tostring(lua_State* L) {
  luaL_checkany(L, 1);
  push_plain_string(L, 1);
  return 1;
}

// Pushes what tostring shows of the value at `index` (see plain_tostring).
void LuaSandbox::push_plain_string(lua_State* L, int index) {
  index = lua_absindex(L, index);
  const int type = lua_type(L, index);
  if (type == LUA_TTABLE || type == LUA_TFUNCTION || type == LUA_TUSERDATA || type == LUA_TTHREAD ||
      type == LUA_TLIGHTUSERDATA) {
    if (luaL_getmetafield(L, index, "__tostring") != LUA_TNIL) {
      lua_pop(L, 1);  // luaL_tolstring calls it
    } else {
      const int name = luaL_getmetafield(L, index, "__name");
      if (name == LUA_TSTRING) return;
      if (name != LUA_TNIL) lua_pop(L, 1);
      lua_pushstring(L, luaL_typename(L, index));
      return;
    }
  }
  luaL_tolstring(L, index, nullptr);
}

}  // namespace dw::scenarios
