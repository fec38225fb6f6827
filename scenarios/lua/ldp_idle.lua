-- ldp_idle.lua: a program that does nothing but hold `dist`, for LDP-style watchpoints whose
-- actions do the work (scenarios/gradient_ldp.toml). Every module starts far from the root.
program = { vars = { "dist" }, params = { root = 0, far = 1000000 } }

function init(m)
  if m.id ~= m:param("root") then m:set("dist", m:param("far")) end
end

function step(m) end
