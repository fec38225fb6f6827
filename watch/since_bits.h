// An unbounded `since(φ, ψ)` kept incrementally (docs/design.md §4c): over one slot's own variables,
// each module keeps one three-valued bit a step, S(s) = ψ(s) or (φ(s) and S(s − 1)), from
// S(d − 1) = F where d is the first step whose reads of φ and ψ all fall at step 0 or later
// (unknown before it; d ≥ 0, as the parser refuses a since that reads only ahead). A history holds the bits as one more
// column per since, after the program's variables (Program::since_bits), and works each step's bits out as it records a
// frame: a reading then reads `since(...)` as a variable, at its own "now".
#pragma once

#include <cstdint>

#include "watch/evaluator.h"
#include "watch/kleene.h"
#include "watch/program.h"

namespace dw::watch {

// S(s) of one module, given S(s − 1) (`before`; ignored at the first step): `read(variable, step,
// out)` reads the module's own history.
template <class Read>
Truth since_bit(const Program& p, const SinceBit& bit, int64_t s, Truth before, Read&& read,
                EvaluatorScratch& scratch) {
  if (s < bit.first_step) return kUnknown;
  struct Reader {
    Read& read;
    int64_t step;
    Value term(const ValueInstr& in) const {
      int64_t v = 0;
      return read(in.variable, step + in.offset, v) ? known_value(v) : Value{};
    }
    // φ and ψ read one module's own variables: no aggregate, no neighbour, no other slot.
    int open(const AggregateCode&) const { return -1; }
    Value bound(int, const ValueInstr&) const { return {}; }
    uint32_t bound_id(int) const { return 0; }
    Truth bound_adjacent(int, int, uint32_t) const { return kUnknown; }
    uint32_t slot_module(int) const { return 0; }
    Truth slot_adjacent(const ConditionTest&, uint32_t) const { return kUnknown; }
    int64_t now(int) const { return step; }
  } reader{read, s};
  Evaluator e(p, reader, scratch);
  auto next = [&](Truth prior) {
    return kleene_or(e.condition_program(bit.psi), kleene_and(e.condition_program(bit.phi), prior));
  };
  return next(s == bit.first_step ? kFalse : before);
}

}  // namespace dw::watch
