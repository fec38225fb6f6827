// Splits watchpoint text into tokens. `#` starts a comment that runs to the end of the line.
#pragma once

#include <vector>

#include "watch/source.h"
#include "watch/token.h"

namespace dw::watch {

// Returns every token of `source`, ending with one End token.
std::vector<Token> lex(const SourceText& source);

}  // namespace dw::watch
