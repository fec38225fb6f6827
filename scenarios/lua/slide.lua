-- Modules sliding along the top of a row (the paper's §I example), the Lua twin of
-- scenarios/programs/slide.cpp: the same variables, messages and moves, so the same state hashes and
-- matches. It needs a world with bodies ([physics] enabled): it senses its position with
-- m:position() and m:moving(), and moves with m:move(dx, dy, dz).
--
-- Each top module moves one cell along +x by a lattice move when the cell ahead is free or being
-- vacated, so a row of them travels like a train until its head reaches `stop`. Neighbours tell
-- each other where they are and whether they are setting off. `gap` is how many steps the cell
-- ahead must have been free (or its occupant setting off) before a module sets off itself: with
-- gap < 4, adjacent modules set off within four steps of each other, which the §I watchpoint
-- catches.
program = {
  vars = { "cell_x", "started", "moving", "_free_for" },
  params = { gap = 0, layer = 1, stop = 11 },  -- stop: the last cell along x (the C++ twin: the lattice's)
}

function step(m)
  local px, _, pz = m:position()
  local x, z = math.floor(px + 0.5), math.floor(pz + 0.5)
  local moving = m:moving()
  m:set("cell_x", x)
  m:set("moving", moving and 1 or 0)
  local starting = false
  if z == m:param("layer") and not moving then
    -- The cell ahead is free when no neighbour says it is there, or its occupant sets off. At
    -- step 0 nothing has been heard yet, so nothing is known to be free.
    local free = x < m:param("stop") and m.step > 0
    local inbox = m:inbox()  -- words: x, z, setting off
    for i = 1, #inbox do
      local data = inbox[i].data
      if data[1] == x + 1 and data[2] == z and data[3] == 0 then free = false end
    end
    local free_for = free and m:get("_free_for") + 1 or 0
    starting = free_for > m:param("gap")
    m:set("_free_for", starting and 0 or free_for)
    if starting then m:move(1, 0, 0) end
  else
    m:set("_free_for", 0)
  end
  m:set("started", starting and 1 or 0)
  m:broadcast({ x, z, starting and 1 or 0 })
end
