while true do end
program = { vars = { "v" } }
function step(m) end
