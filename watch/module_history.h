// The recent past of one module, as its distributed agent keeps it (paper §III-B): the values of
// the variables the watchpoint reads and the module's neighbour sets, each over exactly the steps
// the watchpoint can still ask for (paper §IV-A), or over the whole run when spans are off.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "watch/program.h"
#include "watch/step_ring.h"

namespace dw::watch {

class ModuleHistory {
 public:
  void configure(const Program& program, bool temporal_spans);

  // Records the module's state at `step`; `values`/`has_value` are indexed by program variable.
  void record(int64_t step, bool present, const int64_t* values, const uint8_t* has_value,
              std::span<const uint32_t> neighbors);

  // The value of a program variable at `step`; false when unknown (absent, missing, before 0).
  bool value(int variable, int64_t step, int64_t& out) const {
    const Value* v = values_[variable].find(step);
    if (v == nullptr || !v->known) return false;
    out = v->value;
    return true;
  }

  // N(m, step), or nullptr when the module was absent then (or the step is unknown).
  const std::vector<uint32_t>* neighbors(int64_t step) const {
    const Neighbors* n = neighbors_.find(step);
    return n != nullptr && n->present ? &n->ids : nullptr;
  }

  bool present(int64_t step) const {
    const Neighbors* n = neighbors_.find(step);
    return n != nullptr && n->present;
  }

  // Values and neighbour ids held now.
  uint64_t held() const;
  // Heap bytes held (storage allocated, whether filled yet or not).
  size_t bytes() const;

 private:
  struct Value {
    int64_t value = 0;
    bool known = false;
  };
  struct Neighbors {
    bool present = false;
    std::vector<uint32_t> ids;
  };
  std::vector<StepRing<Value>> values_;  // per program variable
  StepRing<Neighbors> neighbors_;        // presence and N(m, step)
};

}  // namespace dw::watch
