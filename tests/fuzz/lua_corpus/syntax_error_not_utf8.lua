program = { vars = { "v" } }
-- A syntax error whose message quotes bytes that are not UTF-8 (an unfinished string).
function step(m) m:set("v", 1) end
local s = "€ À¯ í € ô€€ â‚
