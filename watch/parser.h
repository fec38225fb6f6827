// Recursive-descent parser for the watchpoint language (docs/design.md §3) with panic-mode recovery:
// one mistake gives one diagnostic, and parsing goes on to find independent ones.
#pragma once

#include <vector>

#include "watch/ast.h"
#include "watch/diagnostic.h"
#include "watch/source.h"

namespace dw::watch {

// Deepest nesting of parentheses and `not` accepted; deeper input is an error, not a stack overflow.
constexpr int kMaxNesting = 256;
// Most nodes a watchpoint may have: each comparison, neighbor() and `not` is one, and each
// `and` / `or` between two operands one more.
constexpr size_t kMaxNodes = 4096;
// Largest temporal offset, either way: `a.next.next...` past it is an error at its span rather
// than history (and memory) in proportion to the offset.
constexpr int kMaxOffset = 10'000;
// The most hops `within(m, h)` reaches (docs/design.md §4c).
constexpr int kMaxWithinHops = 8;

struct ParseResult {
  Ast ast;
  std::vector<Diagnostic> diagnostics;  // empty when the watchpoint is valid
  bool ok() const { return diagnostics.empty(); }
};

ParseResult parse(const SourceText& source);

}  // namespace dw::watch
