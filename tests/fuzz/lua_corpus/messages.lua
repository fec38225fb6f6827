program = { vars = { "v", "got" }, params = { k = 3 } }
function init(m) m:set("v", m.id * m:param("k")) end
function step(m)
  local got = 0
  for _, msg in ipairs(m:inbox()) do got = got + msg.from + (msg.data[1] or 0) end
  m:set("got", got)
  m:broadcast({ m:get("v"), m:random(10), m:random(0) })
  for _, n in ipairs(m:neighbors()) do m:send(n, { n }) end
  m.step = 7
  pcall(m.send, m, 99, {})
  pcall(function() m.x = 1 end)
  pcall(function() local nb = m:neighbors() nb[5] = 1 end)
  m:set("v", m:get("v") + (1 << 62) * 4)
end
