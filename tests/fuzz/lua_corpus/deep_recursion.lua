program = { vars = { "v" } }
local function f(n) return f(n + 1) + 1 end
function step(m)
  pcall(f, 1)
  local function g(n) if n == 0 then return 0 end return 1 + g(n - 1) end
  m:set("v", g(150))
  string.format("%099d %s %q", 1, string.rep("y", 4000), "\0")
  utf8.char(0x7FFFFFFF) utf8.len(string.rep("\xF4\x8F\xBF\xBF", 1000))
  table.concat({}, ",", 1, 1 << 40)
end
