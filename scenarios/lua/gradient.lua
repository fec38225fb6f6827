-- gradient.lua: every module's hop distance from the root, by flooding.
program = { vars = { "dist" }, params = { root = 0 } }  -- declared variables start at 0

function step(m)
  if m.id == m:param("root") then
    m:set("dist", 0)
  else
    local best = -1
    for _, msg in ipairs(m:inbox()) do  -- { from = id, data = { ints } }, by sender id
      if best < 0 or msg.data[1] + 1 < best then best = msg.data[1] + 1 end
    end
    m:set("dist", best)
  end
  if m:get("dist") >= 0 or m.id == m:param("root") then  -- as of the previous step
    m:broadcast({ m.id == m:param("root") and 0 or m:get("dist") })
  end
end
