program = { vars = { "v" } }
-- An error string whose bytes are not UTF-8 (a lone continuation byte, an overlong '/', a
-- surrogate, a code point past U+10FFFF, a cut sequence), raised in a step: it reaches the
-- session's failure answer, which must stay UTF-8.
function step(m)
  if m.id == 1 then error("bad \x80 \xC0\xAF \xED\xA0\x80 \xF4\x90\x80\x80 \xE2\x82") end
  m:set("v", 1)
end
