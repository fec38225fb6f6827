program = { vars = { "v" } }
-- The same bytes written raw in the source (Lua takes any byte in a string), raised in init.
function init(m) error("raw € À¯ í € ô€€ â‚", 0) end
function step(m) m:set("v", 1) end
