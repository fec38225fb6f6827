// What the detectors observe: the ensemble's state at one step. Modules are addressed by a dense
// index 0..M-1 into the run's module table; variables by a column into the run's variable table.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace dw::watch {

using ModuleId = uint32_t;

// Fixed for a run: which modules may ever appear, and which variable columns frames carry.
struct Universe {
  // Dense index -> stable id. Empty when each id is its index, for `identity_count` modules: a
  // model's lattice, whose ids would take 4 MB at 10^6 modules on every rank.
  std::vector<ModuleId> module_ids;
  std::vector<std::string> variables;  // column -> name
  uint32_t identity_count = 0;
  uint32_t module_count() const {
    return module_ids.empty() ? identity_count : static_cast<uint32_t>(module_ids.size());
  }
  ModuleId id(uint32_t m) const { return module_ids.empty() ? m : module_ids[m]; }
};

struct Frame {
  int64_t step = 0;
  std::span<const uint8_t> present;  // [module]: 1 when the module exists at this step
  // Over ranks a frame carries the variables of a rank's modules only: those from first_module on.
  std::span<const int64_t> values;  // [(module - first_module) * variable_count + column]
  // Same shape: 0 when the module lacks the variable. Empty when every module has every variable
  // (a runtime's frames: a byte a module and variable, all 1, would be 5 MB at 10^6 on every rank).
  std::span<const uint8_t> has_value;
  uint32_t first_module = 0;
  std::span<const uint32_t> nbr_begin;  // [module_count + 1]: CSR offsets into nbrs
  std::span<const uint32_t> nbrs;       // N(m, step) as dense indices, in recorded order
  uint32_t variable_count = 0;
  // The owner of nbr_begin and nbrs when they stay unchanged for as long as it lives (the runtime's
  // neighbour graph): a history of neighbour sets then shares them instead of copying them.
  std::shared_ptr<const void> topology;

  // Whether the module at values[at] has that variable (present or not).
  bool has(size_t at) const { return has_value.empty() || has_value[at]; }
  std::span<const uint32_t> neighbors(uint32_t m) const {
    return nbrs.subspan(nbr_begin[m], nbr_begin[m + 1] - nbr_begin[m]);
  }
};

}  // namespace dw::watch
