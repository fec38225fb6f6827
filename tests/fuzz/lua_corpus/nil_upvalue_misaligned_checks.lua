program = { vars = { "x" }, params = {} }
local C = {}
C.__index = C
function C.new(v) return setmetatable({ v = v }, C) end
function C:get() return self.v end
local keep =M setmetatable({ n = 0 }, { __index = function() return 1 end })
setmetatable(_G, { __index = function(_, k) return nil end })
function step(m)
  local s = 0
  for k, v in pairs({ b = 1, a = 2, [3] = 4 }) do s = s * 7 + v end
  local k = next({ z = 1, y = 2 })
  m:set("x", s + C.new(m.id):get() + keep.other + #tostring({}) + #k)
  m:broadcast({ s })
end
