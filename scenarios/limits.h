// The ranges of the numbers a user gives dwatch, in one place: a scenario key and the command-line
// option that overrides it take the same range and report a value outside it in the same words.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace dw::scenarios {

struct IntegerRange {
  std::string_view key;  // the TOML key, or the option's name without dashes
  int64_t min, max;
};

inline constexpr IntegerRange kStepsRange{"steps", 0, 10'000'000};
inline constexpr IntegerRange kSeedRange{"seed", 0, INT64_MAX};
inline constexpr IntegerRange kHistoryRange{"history_mb", 1, 1'000'000};  // MiB for a session's keyframes
inline constexpr IntegerRange kThreadsRange{"threads", 1, 256};
inline constexpr IntegerRange kSizeRange{"size", 1, 1'000'000};
inline constexpr IntegerRange kMaxLiveRange{"max_live", 0, INT64_MAX};
inline constexpr IntegerRange kLuaSecondsRange{"lua_seconds", 0, 1'000'000'000};

// "'KEY' must be between MIN and MAX, not VALUE": VALUE as the user spelled it, so that a number
// too large for any integer type is shown as written rather than wrapped.
inline std::string out_of_range_message(std::string_view key, int64_t min, int64_t max, std::string_view value) {
  return "'" + std::string(key) + "' must be between " + std::to_string(min) + " and " + std::to_string(max) +
         ", not " + std::string(value);
}

}  // namespace dw::scenarios
