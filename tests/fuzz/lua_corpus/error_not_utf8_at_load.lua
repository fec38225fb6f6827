-- Raised while the chunk loads: the script is refused, its reason holding the bytes.
error("load \x80 \xC0\xAF \xED\xA0\x80 \xF4\x90\x80\x80 \xE2\x82")
