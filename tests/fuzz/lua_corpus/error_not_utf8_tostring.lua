program = { vars = { "v" } }
-- An error value whose __tostring gives bytes that are not UTF-8.
function step(m)
  error(setmetatable({}, { __tostring = function() return "\xED\xA0\x80\xFF" end }))
end
