program = { vars = { "v" } }
function step(m)
  if m.id == 1 then error(setmetatable({}, { __tostring = function() while true do end end })) end
  if m.id == 2 then error() end
  local ok, e = pcall(error, { code = 1 })
  m:set("v", ok and 0 or e.code)
end
