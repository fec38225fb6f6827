-- Token passing on a ring (the paper's Fig. 3 setting), the Lua twin of scenarios/programs/token_ring.cpp:
-- the same variables in the same order, the same messages, so the same state hashes and matches.
-- The module holding the token at step t passes it to its successor (the neighbour with the next
-- id around the ring). Module 0 is the master: it makes the first token at step 0, and a new one
-- when the token has not come back for more than `timeout` steps.
-- Bugs for the watchpoint to find: duplicate_at = S (the holder keeps the token and passes a
-- copy), lose_at = S (the holder drops it). -1: never.
program = {
  vars = { "token", "_since", "_keep" },
  params = { timeout = 16, duplicate_at = -1, lose_at = -1 },
}

-- The neighbour with the smallest id above ours, or else the smallest id: around the ring.
local function successor(m, neighbors)
  for _, id in ipairs(neighbors) do
    if id > m.id then return id end
  end
  return neighbors[1]
end

function step(m)
  local holds = #m:inbox() > 0 or m:get("_keep") ~= 0
  if m.id == 0 then
    local since = holds and 0 or m:get("_since") + 1
    if since > m:param("timeout") or m.step == 0 then holds = true end  -- lost, or not yet made: make one
    m:set("_since", holds and 0 or since)
  end
  m:set("token", holds and 1 or 0)
  m:set("_keep", 0)
  if not holds or m.step == m:param("lose_at") then return end
  local neighbors = m:neighbors()
  if #neighbors == 0 then  -- cut off from the ring: keep the token
    m:set("_keep", 1)
    return
  end
  m:send(successor(m, neighbors), { 1 })
  if m.step == m:param("duplicate_at") then m:set("_keep", 1) end
end
