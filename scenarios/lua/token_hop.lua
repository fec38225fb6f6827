-- token_hop.lua: a token ring whose holder passes the token on the step after it holds it, from
-- its variable, so that whatever sets `token` between two steps decides whether it goes on: the
-- fault injected by scenarios/token_ring_fault.toml's action watchpoint. `pos` is each module's
-- place on the ring, for watchpoints to name a module by. Module 0 makes the first token, and a
-- new one when none has come by for `timeout` steps.
program = { vars = { "token", "pos", "_since" }, params = { timeout = 24 } }

function init(m)
  m:set("pos", m.id)
end

-- The neighbour with the smallest id above ours, or else the smallest id: around the ring.
local function successor(m, neighbors)
  for _, id in ipairs(neighbors) do
    if id > m.id then return id end
  end
  return neighbors[1]
end

function step(m)
  local neighbors = m:neighbors()
  if m:get("token") == 1 and #neighbors > 0 then m:send(successor(m, neighbors), { 1 }) end
  local holds = #m:inbox() > 0
  if m.id == 0 then
    local since = holds and 0 or m:get("_since") + 1
    if m.step == 0 or since > m:param("timeout") then holds, since = true, 0 end
    m:set("_since", since)
  end
  m:set("token", holds and 1 or 0)
end
