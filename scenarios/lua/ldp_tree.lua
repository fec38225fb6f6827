-- ldp_tree.lua: a program that does nothing but hold `dist` and `parent`, for LDP-style
-- watchpoints whose actions build a breadth-first spanning tree (scenarios/bfs_tree_ldp.toml).
-- Every module starts far from the root, and its own parent.
program = { vars = { "dist", "parent" }, params = { root = 0, far = 1000000 } }

function init(m)
  if m.id ~= m:param("root") then m:set("dist", m:param("far")) end
  m:set("parent", m.id)
end

function step(m) end
