// The Lua chunk that puts the sandbox's guards over the libraries a script sees (see
// lua_sandbox.h): each library function whose work grows with its arguments is charged for it
// first, patterns are checked before they run, table.sort is a counted merge sort. Kept apart
// from lua_sandbox.cpp, which runs it, as the one piece of the sandbox written in Lua.
#pragma once

namespace dw::scenarios {

// The guards (see lua_sandbox.h), run once over the libraries' copies the script sees. Each guard
// calls the library's function through pcall and `finish`, so that the function's errors name
// the script's line (not the guard's) and the function (Lua finds its name in the original
// tables, which the script never sees).
inline constexpr const char* kGuards = R"lua(
local G, S, T, U, charge, charge_text, check_pattern, buffered, plain_concat, plain_format, replaying, set_metatable = ...
local type, error, rawget, tonumber, tointeger, ipairs, select, pcall = type, error, rawget, tonumber, math.tointeger, ipairs, select, pcall
local find = S.find
local guards = {}
local function finish(ok, ...)
  if ok then return ... end
  local e = ...
  -- A library function's own message has no place in it: it gets the script's line.
  if type(e) == "string" and not find(e, "^[^\n]-:%d+: ") then error(e, 2) end
  error(e, 0)
end
local function guard(lib, name, make)
  local f = make(lib[name])
  lib[name] = f
  guards[#guards + 1] = f
end
local function integer(v)  -- as the library reads an optional integer argument, or nil
  local n = tonumber(v)
  return n and tointeger(n)
end
local function length(t)  -- #t for a table (its __len included), else 0
  if type(t) ~= "table" then return 0 end
  return integer(#t) or 0
end
local function text(f) return function(...) charge_text(...) return finish(pcall(f, ...)) end end
-- What builds its result in lauxlib's buffer goes through `buffered` (lua_library_buffers.cpp), `false`
-- or the function that makes its arguments plain first.
local function built(f) return function(...) charge_text(...) return finish(buffered(f, false, ...)) end end
for _, name in ipairs { "byte", "sub", "packsize", "unpack" } do guard(S, name, text) end
for _, name in ipairs { "char", "lower", "upper", "reverse", "pack", "dump" } do guard(S, name, built) end
guard(S, "format", function(f) return function(...) charge_text(...) return finish(buffered(f, plain_format, ...)) end end)
for _, name in ipairs { "codepoint", "len", "offset", "codes" } do guard(U, name, text) end
guard(U, "char", built)
guard(G, "tonumber", text)
guard(S, "find", function(f) return function(s, p, init, plain) check_pattern("find", s, p, plain) return finish(pcall(f, s, p, init, plain)) end end)
guard(S, "match", function(f) return function(s, p, init) check_pattern("match", s, p) return finish(pcall(f, s, p, init)) end end)
guard(S, "gmatch", function(f) return function(s, p, init) check_pattern("gmatch", s, p) return finish(pcall(f, s, p, init)) end end)
guard(S, "gsub", function(f) return function(s, p, r, n) check_pattern("gsub", s, p) return finish(buffered(f, replaying, s, p, r, n)) end end)
guard(S, "rep", function(f) return function(s, n, sep)
  local times = tonumber(n)
  if times and times > 0 then
    -- Each copy costs at least a byte: rep loops once a copy, even of nothing.
    local bytes = (type(s) == "string" and #s or 24) + (type(sep) == "string" and #sep or 0)
    charge((bytes > 0 and bytes or 1) * times / 16)
  end
  return finish(buffered(f, false, s, n, sep))
end end)
local function range(i, j)  -- the elements from i to j, as a float (no wrap-around)
  i, j = integer(i), integer(j)
  if i and j and j >= i then return (j + 0.0) - i + 1 end
  return 0
end
guard(T, "concat", function(f) return function(t, sep, i, j)
  charge(range(i or 1, j or length(t)))
  return finish(buffered(f, plain_concat, t, sep, i, j))
end end)
guard(T, "insert", function(f) return function(t, ...) charge(length(t)) return finish(pcall(f, t, ...)) end end)
guard(T, "remove", function(f) return function(t, ...) charge(length(t)) return finish(pcall(f, t, ...)) end end)
guard(T, "move", function(f) return function(a, b, e, t, a2) charge(range(b, e)) return finish(pcall(f, a, b, e, t, a2)) end end)
guard(T, "unpack", function(f) return function(t, i, j) charge(range(i or 1, j or length(t))) return finish(pcall(f, t, i, j)) end end)
guard(T, "pack", text)
guard(G, "setmetatable", function(f) return function(t, mt)
  if type(mt) == "table" then
    if rawget(mt, "__gc") ~= nil then
      error("setmetatable: finalizers (__gc) are not allowed: they run when the collector decides, which differs from run to run", 2)
    end
    if rawget(mt, "__mode") ~= nil then
      error("setmetatable: weak tables (__mode) are not allowed: they lose entries when the collector decides, which differs from run to run", 2)
    end
  end
  return finish(pcall(set_metatable, t, mt))
end end)

-- xpcall on pcall: Lua calls a message handler while it raises the error, and an error raised by
-- a hook (the limits) would run the handler with hooks off, out of the limits' reach. The handler
-- runs here after the stack unwound, which a script without the debug library cannot tell.
local pcall, pack, unpack = pcall, table.pack, table.unpack
local xpcall = function(f, handler, ...)
  if type(handler) ~= "function" then
    error("bad argument #2 to 'xpcall' (function expected, got " .. type(handler) .. ")", 2)
  end
  local results = pack(pcall(f, ...))
  if results[1] then return unpack(results, 1, results.n) end
  return false, (select(2, pcall(handler, results[2])))
end
G.xpcall = xpcall
guards[#guards + 1] = xpcall

-- table.sort: a stable bottom-up merge sort, its comparisons counted as the script's code.
local function less(a, b)
  local ta, tb = type(a), type(b)
  if ta == tb and (ta == "number" or ta == "string" or ta == "table") then return a < b end
  error("attempt to compare " .. ta .. " with " .. tb .. " in table.sort", 3)
end
local function sort(t, lt)
  if type(t) ~= "table" then error("bad argument #1 to 'sort' (table expected, got " .. type(t) .. ")", 2) end
  if lt ~= nil and type(lt) ~= "function" then
    error("bad argument #2 to 'sort' (function expected, got " .. type(lt) .. ")", 2)
  end
  lt = lt or less
  local n = #t
  if type(n) ~= "number" then error("object length is not an integer", 2) end
  if n < 2 then return end
  local a, b = {}, {}
  for i = 1, n do a[i] = t[i] end
  local width = 1
  while width < n do
    local lo = 1
    while lo <= n do
      local mid, hi = lo + width, lo + 2 * width
      if mid > n + 1 then mid = n + 1 end
      if hi > n + 1 then hi = n + 1 end
      local l, r, k = lo, mid, lo
      while l < mid and r < hi do
        if lt(a[r], a[l]) then b[k] = a[r]; r = r + 1 else b[k] = a[l]; l = l + 1 end
        k = k + 1
      end
      while l < mid do b[k] = a[l]; l = l + 1; k = k + 1 end
      while r < hi do b[k] = a[r]; r = r + 1; k = k + 1 end
      lo = hi
    end
    a, b = b, a
    width = width * 2
  end
  for i = 1, n do t[i] = a[i] end
end
T.sort = sort
guards[#guards + 1] = sort
guards[#guards + 1] = less
guards[#guards + 1] = integer
guards[#guards + 1] = length
guards[#guards + 1] = range
guards[#guards + 1] = text
guards[#guards + 1] = built
return guards
)lua";

}  // namespace dw::scenarios
