program = { vars = { "v" } }
function step(m)
  while true do xpcall(function() while true do end end, function() while true do end end) end
end
