#include "watch/diagnostic.h"

#include <algorithm>

namespace dw::watch {

size_t utf8_length(std::string_view text, size_t i) {
  const auto c = uint8_t(text[i]);
  if (c < 0x80) return 1;
  size_t length = 0;
  uint8_t low = 0x80, high = 0xBF;  // the second byte's range
  if (c >= 0xC2 && c <= 0xDF) length = 2;
  else if (c >= 0xE0 && c <= 0xEF) {
    length = 3;
    if (c == 0xE0) low = 0xA0;
    else if (c == 0xED) high = 0x9F;
  } else if (c >= 0xF0 && c <= 0xF4) {
    length = 4;
    if (c == 0xF0) low = 0x90;
    else if (c == 0xF4) high = 0x8F;
  }
  if (length == 0 || i + length > text.size()) return 0;
  const auto second = uint8_t(text[i + 1]);
  if (second < low || second > high) return 0;
  for (size_t k = 2; k < length; ++k)
    if ((uint8_t(text[i + k]) & 0xC0) != 0x80) return 0;
  return length;
}

namespace {

// The line as a terminal may show it: control characters (C0, DEL and C1, whose U+009B a
// terminal takes for the start of an escape sequence) and bytes that are not UTF-8 become '?', one
// for one byte (so that the caret stays under its column), never raw bytes that a terminal would
// act on.
std::string printable(std::string_view line) {
  std::string out(line);
  for (size_t i = 0; i < out.size();) {
    const auto c = uint8_t(out[i]);
    if (c < 0x80) {
      if ((c < 0x20 && c != '\t') || c == 0x7F) out[i] = '?';
      ++i;
      continue;
    }
    const size_t length = utf8_length(out, i);
    if (length == 0) {
      out[i++] = '?';
      continue;
    }
    if (c == 0xC2 && uint8_t(out[i + 1]) < 0xA0) out[i] = out[i + 1] = '?';  // U+0080 to U+009F
    i += length;
  }
  return out;
}

}  // namespace

std::optional<size_t> first_non_utf8(std::string_view text) {
  for (size_t i = 0; i < text.size();) {
    const size_t length = utf8_length(text, i);
    if (length == 0) return i;
    i += length;
  }
  return std::nullopt;
}

std::string format_diagnostic(const SourceText& source, const Diagnostic& d, std::string_view kind) {
  const Location loc = source.locate(d.span.begin);
  std::string out = source.name() + ":" + std::to_string(loc.line) + ":" + std::to_string(loc.column) + ": " +
                    std::string(kind) + ": " + d.message + "\n";
  std::string_view line = source.line_at(d.span.begin);
  uint32_t col0 = loc.column - 1;
  // A long line is shown as a window of kShownColumns around the caret, elided with "...", so
  // that a megabyte on one line gives a message of one line's worth.
  std::string_view before, after;
  if (line.size() > kShownColumns) {
    size_t start = col0 > kShownColumns / 2 ? col0 - kShownColumns / 2 : 0;
    size_t end = std::min(line.size(), start + kShownColumns);
    start = end - kShownColumns;
    const auto continuation = [&](size_t i) { return i < line.size() && (uint8_t(line[i]) & 0xC0) == 0x80; };
    while (start > 0 && continuation(start)) --start;  // whole UTF-8 characters only
    while (end < line.size() && continuation(end)) ++end;
    if (start > 0) before = "...";
    if (end < line.size()) after = "...";
    line = line.substr(start, end - start);
    col0 = static_cast<uint32_t>(col0 - start + before.size());
  }
  const std::string shown = std::string(before).append(printable(line)).append(after);
  out += shown;
  out += '\n';
  // Copy tabs from the source line so that the caret lines up in any tab width.
  // One space per character, not per byte: a UTF-8 character's continuation bytes take none.
  for (uint32_t i = 0; i < col0 && i < shown.size(); ++i)
    if ((uint8_t(shown[i]) & 0xC0) != 0x80) out += shown[i] == '\t' ? '\t' : ' ';
  out += '^';
  const uint32_t width = static_cast<uint32_t>(before.size() + line.size());
  const uint32_t visible = width > col0 ? width - col0 : 0;
  const uint32_t tildes = std::min(d.span.length(), visible);
  for (uint32_t i = 1; i < tildes; ++i) out += '~';
  out += '\n';
  return out;
}

std::string format_diagnostics(const SourceText& source, const std::vector<Diagnostic>& ds) {
  std::string out;
  for (const Diagnostic& d : ds) out += format_diagnostic(source, d);
  return out;
}

}  // namespace dw::watch
