program = { vars = { "v", "w" } }
function step(m)  local s = string.rep("@a", 5%002)
  local ok = pcall(string.find, s,# "*b-")
  m:set("v", ok and 0 or 0)
  local n  =0~ step(m)
  local s = string.rep("a", 3000)
end
