program = { vars = { "v" } }
local mt = { __index = function(t, k) return t[k .. "x"] end }
function step(m)
  local t = setmetatable({}, { __len = function() return 1e300 end, __concat = function(a, b) return a end,
                               __eq = function() return true end, __lt = function() error("lt") end })
  pcall(table.concat, t)
  pcall(table.unpack, t)
  pcall(table.sort, { 3, 1, 2, t }, function(a, b) return a < b end)
  pcall(setmetatable, {}, { __gc = print })
  pcall(setmetatable, {}, { __mode = "k" })
  local deep = setmetatable({}, mt)
  pcall(function() return deep.a end)
  m:set("v", #m:neighbors())
end
