// JSON text read for its structure alone, without parsing it: where arrays and objects open and
// close. For what a parser does not give: positions (where each entry of a trace header's list
// starts, for its errors' columns) and a depth known before parsing (a session request nested
// deeper than nlohmann's recursion can take).
#pragma once

#include <cstddef>
#include <string_view>

namespace dw::sim {

// Calls `at(i, c)` for each '[', '{', ']' and '}' of `text` from `from` on that is outside a
// string, until it returns false.
template <class At>
void for_each_bracket(std::string_view text, size_t from, At at) {
  bool in_string = false;
  for (size_t i = from; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if ((c == '[' || c == '{' || c == ']' || c == '}') && !at(i, c)) {
      return;
    }
  }
}

}  // namespace dw::sim
