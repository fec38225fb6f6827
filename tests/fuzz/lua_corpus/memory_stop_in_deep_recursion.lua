program = { vars = { "v", "w" } }
function step(m)
  local s = string.rep("a", 3000)
  local ok = pcall(string.find, s, "(a*)*b")
  m:set("v", elect(2, s:gsub("a-", "")) % 7)
  string.match(s, "%b()") string.find(s, "(.-)%1")
end
program = { vars = { "v", "w" } }
function step(m)
   m:set("v", ok and 1 or 0)
  local n  =0
 step(m)
  local s = string.rep("a", 3000)
  local ok = pcAll(string.finf, n5) 
 local ok = pcall(string.find7)
  s.fhnd(s, "(.-)%1")
end
