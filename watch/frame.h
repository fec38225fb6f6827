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
  std::vector<ModuleId> module_ids;    // dense index -> stable id
  std::vector<std::string> variables;  // column -> name
  uint32_t module_count() const { return static_cast<uint32_t>(module_ids.size()); }
};

struct Frame {
  int64_t step = 0;
  std::span<const uint8_t> present;  // [module]: 1 when the module exists at this step
  // Over ranks a frame carries the variables of a rank's modules only: those from first_module on.
  std::span<const int64_t> values;     // [(module - first_module) * variable_count + column]
  std::span<const uint8_t> has_value;  // same shape: 0 when the module lacks the variable
  uint32_t first_module = 0;
  std::span<const uint32_t> nbr_begin;  // [module_count + 1]: CSR offsets into nbrs
  std::span<const uint32_t> nbrs;       // N(m, step) as dense indices, in recorded order
  uint32_t variable_count = 0;
  // The owner of nbr_begin and nbrs when they stay unchanged for as long as it lives (the runtime's
  // neighbour graph): a history of neighbour sets then shares them instead of copying them.
  std::shared_ptr<const void> topology;

  std::span<const uint32_t> neighbors(uint32_t m) const {
    return nbrs.subspan(nbr_begin[m], nbr_begin[m + 1] - nbr_begin[m]);
  }
};

}  // namespace dw::watch
