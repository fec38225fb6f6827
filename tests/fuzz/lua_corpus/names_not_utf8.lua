program = { vars = { "v" } }
-- A variable name that is not UTF-8, given to m:set and m:get: the error names it.
function step(m)
  if m.id == 0 then m:set("\xF4\x90\x80\x80", 1) end
  m:set("v", m:get("\xC0\xAF"))
end
