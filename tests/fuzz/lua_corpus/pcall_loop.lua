program = { vars = { "v" } }
function step(m)
  while true do pcall(function() while true do end end) end
end
