program = { vars = { "v" } }
function step(m)
  local t = {}
  while true do t[#t + 1] = { m.id, m.step, tostring(#t) } end
end
