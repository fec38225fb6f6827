-- cluster_heads.lua: modules of a square lattice `width` wide grouped in clusters of 3 x 3 cells
-- (fewer at the edges: clusters of varying size), each headed by its least id, for a `component`
-- watchpoint (scenarios/cluster_heads.toml). What a clustering protocol would settle on, set at
-- the start.
-- The planted bug: module `usurper` declares itself a head too at step `usurp_at`.
program = {
  vars = { "cluster", "head" },
  params = { width = 8, usurper = -1, usurp_at = -1 },
}

function init(m)
  local width = m:param("width")
  local x, y = m.id % width, m.id // width
  local across = (width + 2) // 3
  m:set("cluster", (y // 3) * across + x // 3)
  m:set("head", (x % 3 == 0 and y % 3 == 0) and 1 or 0)
end

function step(m)
  if m.id == m:param("usurper") and m.step == m:param("usurp_at") then m:set("head", 1) end
end
