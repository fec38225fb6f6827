program = { vars = { "v" } }
function step(m)
  local s = ("ab"):rep(1 << 19)
  local n = 0
  while true do if s == s .. "" then n = n + 1 end end
end
