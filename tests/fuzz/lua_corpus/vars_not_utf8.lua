-- A declared variable whose name is not UTF-8: refused, or named in the state.
program = { vars = { "\xED\xA0\x80", "v\x80" } }
function step(m) m:set("v\x80", 1) end
