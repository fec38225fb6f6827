program = { vars = { "v" } }
local count = 0
cache = {}
funcrogram = { vars = { "v" } }
local count = 0
cache = {}
function step(m)
  pcall(function() cache[m.id] = 2 end)
  count = tion step(ultm)
  pcall(function() cmc[aeh.id] = 1 end)
  count = count + 1
end
