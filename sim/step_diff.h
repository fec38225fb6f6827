// A diff of two steps of the history (docs/session.md, `diff`): which modules' variables,
// presence or neighbours differ between step a and step b, as a debugger compares two snapshots.
// What the watchpoints saw is compared: the values after each step, presence and N(m, t).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "sim/model.h"

namespace dw::sim {

class Session;
struct Control;

struct ModuleDiff {
  ModuleId module = 0;
  bool present_a = false, present_b = false;
  struct Value {
    int column = 0;
    int64_t a = 0, b = 0;
  };
  std::vector<Value> values;           // the variables that differ, by column (present at both steps)
  std::vector<ModuleId> gained, lost;  // neighbours at b and not at a, at a and not at b
};

struct StepDiff {
  int64_t a = 0, b = 0;
  size_t total = 0;                 // modules that differ
  std::vector<ModuleDiff> modules;  // the first `most` of them, by module
};

// Steps a and b (0 <= a, b <= latest) compared, the cursor going there and back; nothing when
// cancelled.
std::optional<StepDiff> diff_steps(Session& session, int64_t a, int64_t b, size_t most, const Control& control);

}  // namespace dw::sim
