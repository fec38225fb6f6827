program = { vars = { "v" } }
function step(m)
  local z = m:get("v")
  local s = 3 % 00
  m:set("v", s + z)
end
