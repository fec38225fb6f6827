// Text that reaches an answer, always UTF-8: every answer is JSON, and a byte that is not UTF-8
// made the JSON writer throw and ended the session (a Lua `error("\xff")`, a file name of
// surrogates). The check is watch::first_non_utf8, RFC 3629's: no surrogates (U+D800..U+DFFF), no
// overlong forms, nothing past U+10FFFF.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

namespace dw::shell {

// `text` with each byte that is not part of a UTF-8 character replaced by U+FFFD: what an error
// message holding another's bytes (a Lua error string) says.
std::string replace_invalid_utf8(std::string_view text);

// The one way an answer becomes text, as `dwatch session` writes it: one line of JSON, each byte
// of its strings that is not UTF-8 written as U+FFFD (the requests and scripts are refused before
// they run when they are not UTF-8; what is left is what others said: Lua's error strings).
std::string answer_line(const nlohmann::ordered_json& answer);

}  // namespace dw::shell
