// Integer command-line options checked against the same range, and with the same message, as the
// scenario key they override (scenarios/limits.h). The option's text is checked before it is
// converted, so "-1" for an unsigned count or 18446744073709551615 never wraps: both are bad input.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "scenarios/limits.h"

namespace dw::shell {

// A validator: the text must be a decimal integer within `range`.
CLI::Validator in_range(scenarios::IntegerRange range);

// Adds `--NAME` reading into `target` (an integer, or an optional integer), checked by in_range.
template <typename T>
CLI::Option* add_integer_option(CLI::App& cmd, const std::string& names, T& target, scenarios::IntegerRange range,
                                const std::string& description) {
  return cmd.add_option(names, target, description)->check(in_range(range));
}

}  // namespace dw::shell
