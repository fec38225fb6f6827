// Tokens of the watchpoint language (DESIGN §3).
#pragma once

#include <cstdint>
#include <string>

#include "watch/source.h"

namespace dw::watch {

enum class TokenKind : uint8_t {
  Name,
  Integer,     // fits in int64 (value), or overflowed (overflow = true)
  NonInteger,  // 1.5, 2e3: lexed so that the parser can say "non-integer constant"
  // keywords
  Modules,
  Not,
  And,
  Or,
  Neighbor,
  Last,
  Next,
  // punctuation
  LParen,
  RParen,
  Semicolon,
  Dot,
  Comma,
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
  int64_t value = 0;      // Integer
  bool overflow = false;  // Integer out of int64 range
  std::string message;    // Invalid
};

bool is_keyword(TokenKind k);
bool is_comparison(TokenKind k);
// How a token kind is spelled in messages: "'and'", "')'", "a name", "end of input".
std::string describe(TokenKind k);

}  // namespace dw::watch
