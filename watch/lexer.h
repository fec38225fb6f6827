// Splits watchpoint text into tokens. `#` starts a comment that runs to the end of the line.
#pragma once

#include <memory>
#include <vector>

#include "watch/source.h"
#include "watch/token.h"

namespace dw::watch {

class Lexer;

// The tokens of `source` one at a time, so that a parser holds a few of them rather than the whole
// input's (a token is ~10 times the bytes it spells).
class TokenStream {
 public:
  explicit TokenStream(const SourceText& source);
  ~TokenStream();
  TokenStream(const TokenStream&) = delete;
  TokenStream& operator=(const TokenStream&) = delete;
  // The next token; End at the end of the input, and again after it.
  Token next();

 private:
  std::unique_ptr<Lexer> lexer_;
};

// Returns every token of `source`, ending with one End token.
std::vector<Token> lex(const SourceText& source);

// Whether `word` lexes as one name (letters, digits and _, not starting with a digit, at most
// kMaxNameLength bytes) that a watchpoint can read after '.': no reserved word such as `and` or
// `last` (keywords of expressions, such as `count`, are names there): what a program's variable
// must be called for a watchpoint to read it.
inline constexpr size_t kMaxNameLength = 255;
bool is_name(std::string_view word);

}  // namespace dw::watch
