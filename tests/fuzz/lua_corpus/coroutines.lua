program = { vars = { "v" } }
function step(m)
  local co = coroutine and coroutine.create(function() while true do coroutine.yield() end end)
  m:set("v", co and 1 or 2)
end
