// Source text of a watchpoint and spans into it.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace dw::watch {

// A half-open byte range [begin, end) in a SourceText. Every token and AST node carries one so
// that a diagnostic can point at the exact spot.
struct Span {
  uint32_t begin = 0;
  uint32_t end = 0;
  uint32_t length() const { return end - begin; }
  static Span cover(Span a, Span b) { return {a.begin < b.begin ? a.begin : b.begin, a.end > b.end ? a.end : b.end}; }
};

struct Location {
  uint32_t line = 1;    // 1-based
  uint32_t column = 1;  // 1-based, in bytes
};

// The text being parsed and the name it is reported under (a file path, or "<command line>").
class SourceText {
 public:
  // `base`: where the text starts in a larger file its spans count in (a watchpoint written in a
  // scenario file: its diagnostics point into that file, and it keeps only its own text).
  SourceText(std::string name, std::string text, uint32_t base = 0)
      : name_(std::move(name)), text_(std::move(text)), base_(base) {}

  const std::string& name() const { return name_; }
  const std::string& text() const { return text_; }
  uint32_t base() const { return base_; }
  std::string_view slice(Span s) const { return std::string_view(text_).substr(s.begin - base_, s.length()); }

  Location locate(uint32_t offset) const;
  // The whole line holding `offset`, without its line break.
  std::string_view line_at(uint32_t offset) const;

 private:
  std::string name_;
  std::string text_;
  uint32_t base_ = 0;
};

}  // namespace dw::watch
