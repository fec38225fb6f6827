program = { vars = { "v" } }
function step(m)
  local s = string.rep("x", 1 << 20)
  local t = {}
  for i = 1, 100 do t[i] = s .. i end
  m:set("v", #t)
end
