// An integer of the watchpoint language (docs/design.md §4b): an int64, or Unknown.
#pragma once

#include <cstdint>

namespace dw::watch {

struct Value {
  int64_t value = 0;
  bool known = false;
  bool operator==(const Value&) const = default;
};

inline Value known_value(int64_t v) { return {v, true}; }

}  // namespace dw::watch
