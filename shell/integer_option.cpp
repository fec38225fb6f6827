#include "shell/integer_option.h"

#include <charconv>

namespace dw::shell {

CLI::Validator in_range(scenarios::IntegerRange range) {
  return CLI::Validator(
      [range](std::string& text) -> std::string {
        int64_t value = 0;
        const char* end = text.data() + text.size();
        const auto [stop, error] = std::from_chars(text.data(), end, value);
        if (text.empty() || stop != end || (error != std::errc() && error != std::errc::result_out_of_range))
          return "'" + std::string(range.key) + "' must be an integer, not '" + text + "'";
        if (error == std::errc::result_out_of_range || value < range.min || value > range.max)
          return scenarios::out_of_range_message(range.key, range.min, range.max, text);
        return {};
      },
      "INT in [" + std::to_string(range.min) + " - " + std::to_string(range.max) + "]");
}

}  // namespace dw::shell
