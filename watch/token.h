// Tokens of the watchpoint language (docs/design.md §3).
#pragma once

#include <cstdint>
#include <string>

#include "watch/source.h"

namespace dw::watch {

enum class TokenKind : uint8_t {
  Name,
  Integer,     // a magnitude up to 2^63 (value), or past it (overflow = true); never signed
  NonInteger,  // 1.5, 2e3: lexed so that the parser can say "non-integer constant"
  // keywords
  Modules,
  Not,
  And,
  Or,
  Neighbor,
  Last,
  Next,
  // keywords of expressions and actions (docs/design.md §4b): reserved for slot and bound names, but a
  // variable may be named by one after '.' (`a.count`)
  In,
  Neighbors,
  Count,
  Sum,
  Min,
  Max,
  Abs,
  Then,
  Set,
  Remove,
  // keywords of windows in time and built-ins (docs/design.md §4c), the same rule as those above
  Once,
  Historically,
  Since,
  Times,
  Id,
  Within,
  All,
  Argmin,
  Argmax,
  Component,
  // punctuation
  LParen,
  RParen,
  Semicolon,
  Dot,
  Comma,
  Colon,
  LBracket,
  RBracket,
  // arithmetic
  Plus,
  Minus,
  Star,
  Slash,
  Percent,
  // comparison operators
  Less,
  Greater,
  Equal,
  NotEqual,
  GreaterEqual,
  LessEqual,
  Invalid,  // a character or sequence that is not part of the language; `message` says why
  End,
};

struct Token {
  TokenKind kind = TokenKind::End;
  Span span;
  uint64_t value = 0;     // Integer: its magnitude; a '-' before it is a token of its own
  bool overflow = false;  // Integer past 2^63 (2^63 itself is -9223372036854775808's magnitude)
  std::string message;    // Invalid
};

// Any keyword: none names a slot or a bound name.
bool is_keyword(TokenKind k);
// The paper's keywords (docs/design.md §3), reserved everywhere, variable names included.
bool is_reserved(TokenKind k);
bool is_comparison(TokenKind k);
// How a token kind is spelled in messages: "'and'", "')'", "a name", "end of input".
std::string describe(TokenKind k);

}  // namespace dw::watch
