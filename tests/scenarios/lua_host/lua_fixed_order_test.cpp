// What Lua leaves to its hash seed and to addresses (scenarios/lua_host/lua_fixed_order.cpp): the same in
// every state, so that a script computes the same values on every run and every thread.
#include <gtest/gtest.h>

#include <string>

#include "scenarios/lua_host/lua_sandbox.h"

namespace dw::scenarios {
namespace {

// What `code` returns (as a string), or its error, run counted in a new sandbox.
std::string result(const std::string& code) {
  LuaSandbox box("x.lua", {});
  lua_State* L = box.state();
  EXPECT_EQ(luaL_loadbufferx(L, code.data(), code.size(), "@x.lua", "t"), LUA_OK) << lua_tostring(L, -1);
  const bool ok = box.call(0, 1, true) == LuaSandbox::Outcome::kOk;
  const std::string text = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "(not a string)";
  return ok ? text : "error: " + text;
}

constexpr const char* kKeys = "local t = { b = 1, a = 2, [3] = 0, c = 3, [1.5] = 0, [true] = 0, [-2] = 0, ab = 0 }\n";

TEST(LuaFixedOrder, PairsVisitsNumbersThenStringsThenBooleans) {
  // Lua's own order for these keys depends on the state's hash seed: run in many states, it
  // would not always be this one.
  for (int state = 0; state < 8; ++state)
    EXPECT_EQ(result(std::string(kKeys) + "local s = '' for k in pairs(t) do s = s .. tostring(k) .. ',' end return s"),
              "-2,1.5,3,a,ab,b,c,true,");
  // A key set to nil in the loop is passed over, the others still come.
  EXPECT_EQ(result(std::string(kKeys) +
                   "local s = '' for k in pairs(t) do t.b = nil s = s .. tostring(k) .. ',' end return s"),
            "-2,1.5,3,a,ab,c,true,");
  // __pairs is honoured, as by Lua's pairs.
  EXPECT_EQ(result("local t = setmetatable({}, { __pairs = function() return function(_, k) if not k then return 7 end "
                   "end, nil, nil end }) for k in pairs(t) do return tostring(k) end"),
            "7");
}

TEST(LuaFixedOrder, NextFollowsTheSameOrder) {
  EXPECT_EQ(result(std::string(kKeys) + "local s, k = '', next(t) while k ~= nil do s = s .. tostring(k) .. ',' "
                                        "k = next(t, k) end return s"),
            "-2,1.5,3,a,ab,b,c,true,");
  EXPECT_EQ(result("return tostring(next({}))"), "nil");
  EXPECT_EQ(result("local k, v = next({ x = 5 }) return k .. v"), "x5");
}

TEST(LuaFixedOrder, AKeyWithNoPlaceInTheOrderIsAnError) {
  for (const char* loop : {"for k in pairs(t) do end", "local k = next(t)"}) {
    const std::string e = result(std::string("local t = { [{}] = 1, a = 2 }\n") + loop + "\nreturn 'ran'");
    EXPECT_NE(e.find("x.lua:2: "), std::string::npos) << e;
    EXPECT_NE(e.find("the table has a key that is a table, whose place among the keys would differ from run to run"),
              std::string::npos)
        << e;
  }
}

TEST(LuaFixedOrder, NoAddressIsShown) {
  EXPECT_EQ(result("return tostring({}) .. ',' .. tostring(type) .. ',' .. string.format('%s,%5.2s', {}, {})"),
            "table,function,table,   ta");
  EXPECT_EQ(result("return tostring(setmetatable({}, { __tostring = function() return 'me' end })) .. ',' .. "
                   "tostring(setmetatable({}, { __name = 'Vec' })) .. ',' .. tostring(12) .. tostring(nil)"),
            "me,Vec,12nil");
  const std::string e = result("local s = string.format('%p', {})\nreturn s");
  EXPECT_NE(e.find("x.lua:1: string.format: %p shows an address"), std::string::npos) << e;
}

}  // namespace
}  // namespace dw::scenarios
