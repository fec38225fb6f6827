-- parent_flap.lua: a breadth-first tree by flooding, for a `times` watchpoint
-- (scenarios/parent_flap.toml). Each module keeps its hop distance from the root and its parent,
-- the neighbour of least distance (ties to the least id, the inbox being in sender order). In
-- synchronous flooding the first distance a module hears is its own for good, so a parent changes
-- once.
-- The planted bug: from step `flap_from` to `flap_to` - 1, module `flapper` re-picks its parent each
-- step between its first two neighbours, alternating.
program = {
  vars = { "dist", "parent" },
  params = { root = 0, flapper = -1, flap_from = -1, flap_to = -1 },
}

function init(m)
  m:set("dist", m.id == m:param("root") and 0 or -1)
  m:set("parent", m.id)
end

function step(m)
  local dist, parent = m:get("dist"), m:get("parent")  -- as of the previous step
  if m.id ~= m:param("root") then
    local inbox = m:inbox()
    for _, msg in ipairs(inbox) do
      local d = msg.data[1]
      if dist < 0 or d + 1 < dist then dist, parent = d + 1, msg.from end
    end
    if m.id == m:param("flapper") and m.step >= m:param("flap_from") and m.step < m:param("flap_to") and #inbox >= 2 then
      parent = inbox[(m.step % 2) + 1].from
    end
    m:set("dist", dist)
    m:set("parent", parent)
  end
  if dist >= 0 then m:broadcast({ dist }) end
end
