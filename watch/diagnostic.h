// Diagnostics in the compiler style: `file:line:col: error: message`, the source line, and a
// caret under the span. Errors are collected, never thrown.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "watch/source.h"

namespace dw::watch {

struct Diagnostic {
  Span span;
  std::string message;
};

// Columns of a long source line shown around the caret (the rest elided with "...").
constexpr size_t kShownColumns = 160;
// The bytes of the UTF-8 character at text[i], or 0 when none starts there, as RFC 3629's table
// says: a stray continuation byte, a character cut short, and, by the second byte's range, overlong
// forms (C0, C1, E0 80..9F, F0 80..8F), surrogates (ED A0..BF) and code points past U+10FFFF
// (F4 90..BF; F5..FF lead nothing).
size_t utf8_length(std::string_view text, size_t i);
// Where `text` stops being UTF-8 (the first byte no character starts at), or nothing when it all is.
std::optional<size_t> first_non_utf8(std::string_view text);
// Renders one diagnostic: the location line, the source line, and `^~~~` under the span.
// `kind` is "error", or "warning" for what does not stop anything.
std::string format_diagnostic(const SourceText& source, const Diagnostic& d, std::string_view kind = "error");

// Renders every diagnostic, one after another.
std::string format_diagnostics(const SourceText& source, const std::vector<Diagnostic>& ds);

}  // namespace dw::watch
