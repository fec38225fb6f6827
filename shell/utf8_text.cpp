#include "shell/utf8_text.h"

#include <cstdint>

namespace dw::shell {
namespace {

// The bytes of the UTF-8 character at text[i], or 0 when none starts there. The second byte's
// range is what rules out overlong forms (E0 80..9F, F0 80..8F), surrogates (ED A0..BF) and
// code points past U+10FFFF (F4 90..BF; F5..FF lead nothing), as RFC 3629's table says.
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

}  // namespace

std::optional<size_t> first_invalid_utf8(std::string_view text) {
  for (size_t i = 0; i < text.size();) {
    const size_t length = utf8_length(text, i);
    if (length == 0) return i;
    i += length;
  }
  return std::nullopt;
}

std::string replace_invalid_utf8(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size();) {
    const size_t length = utf8_length(text, i);
    if (length == 0) {
      out += "\xEF\xBF\xBD";  // U+FFFD REPLACEMENT CHARACTER
      ++i;
    } else {
      out.append(text, i, length);
      i += length;
    }
  }
  return out;
}

std::string answer_line(const nlohmann::ordered_json& answer) {
  return answer.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

}  // namespace dw::shell
