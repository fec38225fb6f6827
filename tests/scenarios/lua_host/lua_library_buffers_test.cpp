// Library functions building their results in lauxlib's buffer (scenarios/lua_host/lua_library_buffers.cpp)
// under the sandbox's memory cap.
#include <gtest/gtest.h>

#include <string>

#include "scenarios/lua_host/lua_sandbox.h"

namespace dw::scenarios {
namespace {

using Outcome = LuaSandbox::Outcome;

// Lua asks again after a full collection when the cap refuses it; lauxlib's buffer (string.rep,
// format, gsub, table.concat ...) asks the allocator directly. A function building its result
// there must meet the cap only when what the state holds does not fit, never because of garbage
// the collector has not taken yet: an uncounted try taken back leaves more of it than a counted
// run, and the two must agree. Here the garbage is old (it survived a full collection), which the
// young collections of the generational collector never take.
TEST(LuaLibraryBuffers, GarbageNeverMakesALibraryFunctionMeetTheMemoryCap) {
  LuaLimits limits;
  limits.memory_bytes = 1u << 20;
  const auto after_old_garbage = [&](const std::string& code) {
    LuaSandbox box("x.lua", limits);
    lua_State* L = box.state();
    EXPECT_EQ(luaL_loadstring(L, "local a = ('x'):rep(196608) big = a .. a .. a .. a"), LUA_OK);
    EXPECT_EQ(box.call(0, 0, true), Outcome::kOk);
    lua_gc(L, LUA_GCCOLLECT);
    const std::string chunk = "big = nil\n" + code;
    EXPECT_EQ(luaL_loadbufferx(L, chunk.data(), chunk.size(), "@x.lua", "t"), LUA_OK);
    const Outcome outcome = box.call(0, 1, true);
    return outcome == Outcome::kOk ? std::string(luaL_tolstring(L, -1, nullptr))
                                   : "failed: " + std::string(lua_isstring(L, -1) ? lua_tostring(L, -1) : "");
  };
  EXPECT_EQ(after_old_garbage("return #('b'):rep(400000)"), "400000");
  EXPECT_EQ(after_old_garbage("return #table.concat({('b'):rep(150000), ('c'):rep(150000)})"), "300000");
  // Tried again after the collection, the script's own code still runs once per value: the
  // replacement function once per match, __index and __tostring once per read.
  const std::string piece = "local piece, calls = ('b'):rep(300), 0\n";
  EXPECT_EQ(
      after_old_garbage(piece + "local s = ('a'):rep(1000):gsub('a', function() calls = calls + 1 return piece end)\n"
                                "return calls .. ' ' .. #s"),
      "1000 300000");
  EXPECT_EQ(after_old_garbage(
                piece + "local t = setmetatable({}, {__index = function(_, c) calls = calls + 1 return piece end})\n"
                        "local s = ('a'):rep(1000):gsub('a', t)\n"
                        "return calls .. ' ' .. #s"),
            "1000 300000");
  EXPECT_EQ(
      after_old_garbage(piece + "local t = setmetatable({}, {__index = function() calls = calls + 1 return piece end,\n"
                                "                            __len = function() return 1000 end})\n"
                                "local s = table.concat(t)\n"
                                "return calls .. ' ' .. #s"),
      "1000 300000");
  EXPECT_EQ(
      after_old_garbage("local calls, wide = 0, ('b'):rep(100000)\n"
                        "local t = setmetatable({}, {__tostring = function() calls = calls + 1 return wide end})\n"
                        "local s = string.format('%s%d%s', t, 7, t)\n"
                        "return calls .. ' ' .. #s"),
      "2 200001");
  // What the state holds and does not fit is still a memory stop, however it is tried.
  EXPECT_EQ(after_old_garbage("keep = ('k'):rep(400000)\nreturn #('b'):rep(400000)"),
            "failed: x.lua: not enough memory: a script's Lua state may hold at most 1 MiB");
}

}  // namespace
}  // namespace dw::scenarios
