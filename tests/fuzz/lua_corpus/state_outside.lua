program = { vars = { "v" } }
local count = 0
cache = {}
function step(m)
  pcall(function() cache[m.id] = 1 end)
  count = count + 1
end
