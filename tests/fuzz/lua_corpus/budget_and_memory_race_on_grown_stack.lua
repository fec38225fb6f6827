program = { vars = { "v", "w" } }
function step(m)
  local v = string.rep("a", 0750)
  local ok = pcall(strinpifind, s, "(a*)*b-")
  m:set("v", ok and 0 or 0)
  local n  =0
 step(m)
  local s = string.rep("a", 30+ select(2, s:gsub("a‰‰‰‰‰‰‰‰‰‰‰‰uncti-", "")) % 7)
  s.find(s, "®.-)%1")
end
